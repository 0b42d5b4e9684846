"""springpend tests: the C source of a helper, built with lcms2 by the tests
that need ICC profiles a colour manager converts by otherwise than sRGB
(test_attack15_readers.py, test_attack16_readers.py): `mkicc EVIL CICP`
writes evil.icc, sRGB's profile with an A2B0 table that is sRGB's on every
15th level and inverts other colours (attack15 #11's reproduction), and
cicp.icc, lcms2's sRGB profile with a cicp tag (BT.2020, PQ); it prints
what lcms2 converts 200,100,50 to through evil.icc."""

HELPER = r"""
#include <lcms2.h>
#include <stdio.h>
/* evil.icc: sRGB's profile with an A2B0 CLUT of 35 nodes a side that is sRGB's on the nodes
   of every 15th level, on the faces at 0 and on the grey diagonal, and every other node's
   colour's complement (attack15 #11's reproduction); cicp.icc: lcms2's sRGB profile with a
   cicp tag (BT.2020, PQ). Prints what lcms2 converts 200,100,50 to through evil.icc. */
#define NODES 35
static cmsHTRANSFORM to_lab;
static int sampler(const cmsUInt16Number in[], cmsUInt16Number out[], void *cargo)
{
    cmsUInt16Number rgb[3] = {in[0], in[1], in[2]};
    int k[3], odd = 0, zero = 0;
    (void)cargo;
    for (int c = 0; c < 3; c++) {
        k[c] = (int)((in[c] * (NODES - 1) + 32767) / 65535);
        odd |= k[c] & 1, zero |= k[c] == 0;
    }
    if (odd && !zero && !(k[0] == k[1] && k[1] == k[2]))
        for (int c = 0; c < 3; c++)
            rgb[c] = 65535 - in[c];
    cmsDoTransform(to_lab, rgb, out, 1);
    return 1;
}
int main(int argc, char **argv)
{
    if (argc != 3)
        return 2;
    to_lab = cmsCreateTransform(cmsCreate_sRGBProfile(), TYPE_RGB_16, cmsCreateLab4Profile(NULL),
                                TYPE_Lab_16, INTENT_RELATIVE_COLORIMETRIC, cmsFLAGS_NOOPTIMIZE);
    cmsHPROFILE p = cmsCreate_sRGBProfile();
    cmsSetProfileVersion(p, 4.3);
    cmsSetPCS(p, cmsSigLabData);
    cmsPipeline *pl = cmsPipelineAlloc(NULL, 3, 3);
    cmsStage *clut = cmsStageAllocCLut16bit(NULL, NODES, 3, 3, NULL);
    cmsStageSampleCLut16bit(clut, sampler, NULL, 0);
    cmsPipelineInsertStage(pl, cmsAT_END, cmsStageAllocToneCurves(NULL, 3, NULL));
    cmsPipelineInsertStage(pl, cmsAT_END, clut);
    cmsPipelineInsertStage(pl, cmsAT_END, cmsStageAllocToneCurves(NULL, 3, NULL));
    cmsWriteTag(p, cmsSigAToB0Tag, pl);
    if (!cmsSaveProfileToFile(p, argv[1]))
        return 1;
    cmsHPROFILE q = cmsCreate_sRGBProfile();
    cmsVideoSignalType pq = {9, 16, 0, 1};
    cmsSetProfileVersion(q, 4.4);
    if (!cmsWriteTag(q, cmsSigcicpTag, &pq) || !cmsSaveProfileToFile(q, argv[2]))
        return 1;
    cmsHPROFILE evil = cmsOpenProfileFromFile(argv[1], "r");
    cmsHTRANSFORM t = cmsCreateTransform(evil, TYPE_RGB_8, cmsCreate_sRGBProfile(), TYPE_RGB_8,
                                         INTENT_PERCEPTUAL, 0);
    unsigned char in[3] = {200, 100, 50}, out[3];
    cmsDoTransform(t, in, out, 1);
    printf("%d %d %d\n", out[0], out[1], out[2]);
    return 0;
}
"""
