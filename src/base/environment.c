/* springpend: the environment that produced an image (environment.h). */
#include <errno.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gnu/libc-version.h>

#include <ft2build.h>
#include FT_FREETYPE_H
#include <fontconfig/fontconfig.h>
#include <fribidi.h>
#include <hb.h>
#include <png.h>
#include <zlib.h>

#include "springpend/common.h"
#include "springpend/environment.h"
#include "sinks/av_module.h"
#include "digest.h"
#include "embedded.h"

/* The version after `word` in s ("Mesa 22.3.6" -> "22.3.6"), up to a blank,
 * ',' or ')', into out; "unknown" when s lacks it. */
static void version_after(const char *s, const char *word, char *out, size_t size)
{
    const char *p = s ? strstr(s, word) : NULL;
    if (!p) {
        snprintf(out, size, "unknown");
        return;
    }
    p += strlen(word);
    snprintf(out, size, "%.*s", (int)strcspn(p, " ,)"), p);
}

/* SHA-256 of n bytes as hex into hex[65]. */
static void sha256_hex(const void *data, size_t n, char hex[65])
{
    struct sha256_ctx sha;
    sha256_init(&sha);
    sha256_update(&sha, n, data);
    sp_digest_hex(&sha, hex);
}

int sp_environment_text(char *buf, size_t size, const char *renderer, const char *gl_version)
{
    char mesa[64], llvm[64], font[65], ft[32] = "unknown", av[96] = "not loaded";
    FT_Library lib;
    FILE *m = fmemopen(buf, size, "w");
    if (!m) {
        snprintf(buf, size, "springpend: " SP_VERSION "\n");
        return 0;
    }
    if (FT_Init_FreeType(&lib) == 0) {
        FT_Int a, b, c;
        FT_Library_Version(lib, &a, &b, &c);
        snprintf(ft, sizeof(ft), "%d.%d.%d", a, b, c);
        FT_Done_FreeType(lib);
    }
    {
        /* both from the module's libraries: the executable links no FFmpeg.
         * A probe: a module that cannot be loaded is "not loaded" here, said
         * by whatever needs it (a still is written without it) */
        unsigned (*avcodec_version_fn)(void);
        const char *(*av_version_info_fn)(void);
        const int muted = sp_log_muted();
        sp_log_mute(1);
        *(void **)&avcodec_version_fn = sp_av_module_symbol("avcodec_version");
        *(void **)&av_version_info_fn = avcodec_version_fn
                                            ? sp_av_module_symbol("av_version_info") : NULL;
        sp_log_mute(muted);
        if (avcodec_version_fn && av_version_info_fn) {
            unsigned v = avcodec_version_fn();
            snprintf(av, sizeof(av), "%u.%u.%u (FFmpeg %s)", v >> 16, v >> 8 & 255, v & 255,
                     av_version_info_fn());
        }
    }
    version_after(gl_version, "Mesa ", mesa, sizeof(mesa));
    version_after(renderer, "LLVM ", llvm, sizeof(llvm));
    sha256_hex(sp_embed_DejaVuSans_ttf, (size_t)sp_embed_DejaVuSans_ttf_size, font);
    /* the text stack (text.c): shaping, bidi and font lookup */
    const int fc = FcGetVersion();
    char bidi[32];
    snprintf(bidi, sizeof(bidi), "%.*s", (int)strcspn(fribidi_version_info, "\n"),
             fribidi_version_info); /* "(GNU FriBidi) 1.0.8\n..." */
    const char *bidi_v = strrchr(bidi, ' ') ? strrchr(bidi, ' ') + 1 : bidi;
    fprintf(m, "springpend: " SP_VERSION "\nrenderer: %s\ngl: %s\nmesa: %s\nllvm: %s\n"
            "freetype: %s\nharfbuzz: %s\nfribidi: %s\nfontconfig: %d.%d.%d\n"
            "font: DejaVu Sans (embedded in springpend, %lu bytes) sha256 %s\n"
            "zlib: %s\nlibpng: %s\nlibavcodec: %s\n",
            renderer ? renderer : "none", gl_version ? gl_version : "none",
            gl_version ? mesa : "none", renderer ? llvm : "none", ft, hb_version_string(),
            bidi_v, fc / 10000, fc / 100 % 100, fc % 100,
            sp_embed_DejaVuSans_ttf_size, font, zlibVersion(), png_get_libpng_ver(NULL), av);
    fclose(m);
    buf[size - 1] = 0;
    return 0;
}

int sp_environment_add_font(char *buf, size_t size, const char *path, const char hex[65],
                            long long bytes)
{
    char line[512], name[256];
    const char *base = strrchr(path, '/') ? strrchr(path, '/') + 1 : path;
    /* the key is the file's name: ':' and control characters would break
     * the "key: value" lines */
    snprintf(name, sizeof(name), "%s", base);
    for (char *c = name; *c; c++)
        if (*c == ':' || (unsigned char)*c < 32)
            *c = '_';
    const int n = snprintf(line, sizeof(line), "font %s: sha256 %s (%lld bytes)\n", name, hex, bytes);
    const char *at = strstr(buf, "\nzlib: "); /* after the other font lines */
    if (strstr(buf, line))
        return 0; /* already recorded */
    const size_t len = strlen(buf), pos = at ? (size_t)(at - buf) + 1 : len;
    if (len + (size_t)n >= size) {
        sp_log_error("%s: the environment record is full (%zu bytes): it cannot name this "
                     "font and its SHA-256; an image records at most about %zu font files",
                     path, size, size / (size_t)n);
        return SP_E_INPUT;
    }
    memmove(buf + pos + n, buf + pos, len - pos + 1);
    memcpy(buf + pos, line, (size_t)n);
    return 0;
}

int sp_environment_numbers(char *buf, size_t size)
{
    snprintf(buf, size, "springpend: " SP_VERSION "\ncompiler: %s\nlibc: glibc %s\n", __VERSION__,
             gnu_get_libc_version());
    return 0;
}
