/* springpend tests: a font file's provenance is of the bytes it was drawn
 * from (issue 28; attack4.md finding 6). text.c reads a font file once,
 * when its face is opened, and FreeType, HarfBuzz, cairo and the SHA-256
 * in springpend.environment all use those bytes: a file replaced after
 * the face was opened is not read again (the hash was taken by reopening
 * the path, so the record named the new file, not the one drawn). The test
 * shows fontconfig a folder holding a copy of DejaVu Serif, lays text out
 * in it, overwrites the file in place with other bytes, and checks that
 * the environment line holds the first file's SHA-256 and size, computed
 * here with nettle from the copy's own bytes. It also checks the built-in
 * font's name (SP_FONT_EMBEDDED: no system path) in sp_font_files.
 * usage: test_font_bytes TMPDIR   (TAP on stdout) */
#include <nettle/sha2.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "springpend/common.h"
#include "springpend/environment.h"
#include "frame/text.h"
#include "tap.h"

#ifdef NDEBUG
#error "tests need assertions"
#endif

#define SERIF "/usr/share/fonts/truetype/dejavu/DejaVuSerif.ttf"
#define OTHER "/usr/share/fonts/truetype/dejavu/DejaVuSans-Bold.ttf"

/* path's bytes (malloc'd) and their count, or NULL. */
static unsigned char *slurp(const char *path, size_t *n)
{
    FILE *fp = fopen(path, "rb");
    unsigned char *d = NULL;
    long len;
    if (!fp)
        return NULL;
    if (!fseek(fp, 0, SEEK_END) && (len = ftell(fp)) > 0 && !fseek(fp, 0, SEEK_SET) &&
        (d = malloc((size_t)len)) && fread(d, 1, (size_t)len, fp) != (size_t)len) {
        free(d);
        d = NULL;
    }
    if (d)
        *n = (size_t)len;
    fclose(fp);
    return d;
}

static int spit(const char *path, const unsigned char *d, size_t n)
{
    FILE *fp = fopen(path, "wb");
    int ok = fp && fwrite(d, 1, n, fp) == n;
    return fp && !fclose(fp) && ok;
}

static void hex_of(const unsigned char *d, size_t n, char hex[65])
{
    struct sha256_ctx c;
    uint8_t dg[SHA256_DIGEST_SIZE];
    sha256_init(&c);
    sha256_update(&c, n, d);
    sha256_digest(&c, sizeof(dg), dg);
    for (int i = 0; i < SHA256_DIGEST_SIZE; i++)
        snprintf(hex + 2 * i, 3, "%02x", dg[i]);
}

int main(int argc, char **argv)
{
    char dir[4096], font[4200], conf[4200], line[512], env[SP_ENVIRONMENT_MAX] = "";
    char first[65], second[65], files[2048];
    size_t n1 = 0, n2 = 0;
    unsigned char *serif = slurp(SERIF, &n1), *other = slurp(OTHER, &n2);
    if (argc < 2 || !serif || !other) {
        printf("1..0 # SKIP needs TMPDIR and fonts-dejavu (%s, %s)\n", SERIF, OTHER);
        return 77;
    }
    snprintf(dir, sizeof(dir), "%s/font_bytes", argv[1]);
    mkdir(dir, 0755);
    snprintf(font, sizeof(font), "%s/x.ttf", dir);
    snprintf(conf, sizeof(conf), "%s/fonts.conf", dir);
    FILE *cf = fopen(conf, "w");
    if (!cf || !spit(font, serif, n1))
        return 1;
    fprintf(cf, "<?xml version=\"1.0\"?><fontconfig><dir>%s</dir><cachedir>%s/cache</cachedir>"
                "</fontconfig>\n", dir, dir);
    fclose(cf);
    setenv("FONTCONFIG_FILE", conf, 1);
    hex_of(serif, n1, first);
    hex_of(other, n2, second);

    struct sp_font *f = NULL;
    struct sp_font_desc d = {.family = "DejaVu Serif", .px = {12, 14, 18, 24}};
    sp_tap_ok(sp_font_make(&f, &d) == 0, "the family is found in the test's own font folder");
    sp_tap_ok(f && sp_font_width(f, SP_TEXT_NORMAL, "Federpendel") > 0,
              "text is laid out in it (its face opened)");
    /* the file is replaced in place after the face was opened */
    sp_tap_ok(spit(font, other, n2), "the font file is overwritten with other bytes");
    sp_tap_ok(f && sp_font_environment(f, env, sizeof(env)) == 0, "the environment takes the font");
    snprintf(line, sizeof(line), "font x.ttf: sha256 %s (%zu bytes)\n", first, n1);
    sp_tap_ok(strstr(env, line) != NULL,
              "the recorded SHA-256 and size are of the bytes drawn (%.64s, %zu bytes), "
              "not of the file as it is now (%.12s…): %s", first, n1, second, env);
    if (f) {
        sp_font_files(f, files, sizeof(files));
        sp_tap_ok(strstr(files, "/x.ttf") != NULL, "sp_font_files names the file (%s)", files);
    }
    sp_font_destroy(&f);

    struct sp_font *e = NULL;
    struct sp_font_desc de = {.family = "", .px = {12, 14, 18, 24}};
    sp_tap_ok(sp_font_make(&e, &de) == 0 && sp_font_width(e, SP_TEXT_NORMAL, "abc") > 0,
              "the default font lays text out");
    if (e) {
        sp_font_files(e, files, sizeof(files));
        sp_tap_ok(!strcmp(files, SP_FONT_EMBEDDED) &&
                  !strcmp(files, "DejaVu Sans (embedded in springpend)"),
                  "the built-in font is named as built in, by no system path (%s)", files);
    }
    sp_font_destroy(&e);
    free(serif);
    free(other);
    return sp_tap_done();
}
