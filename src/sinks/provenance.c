/* springpend: PNG text chunks naming an image's origin (provenance.h).
 * SHA-256 from nettle: small, and it pulls nothing else into the start of
 * every command (libavutil did: libva, libX11, libOpenCL, libmfx). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/command_line.h"
#include "base/digest.h"
#include "springpend/common.h"
#include "springpend/provenance.h"

/* SHA-256 of the scene's canonical text into hex[65]; the text itself,
 * malloc'd, into *copy. */
static int scene_sha256(const struct sp_scene *scene, char hex[65], char **copy)
{
    int n = sp_scene_canonical(scene, NULL, 0);
    char *text = malloc((size_t)n + 1);
    struct sha256_ctx sha;
    if (!text) {
        sp_log_error("out of memory");
        return SP_E_NOMEM;
    }
    sp_scene_canonical(scene, text, (size_t)n + 1);
    sha256_init(&sha);
    sha256_update(&sha, (size_t)n, (const uint8_t *)text);
    sp_digest_hex(&sha, hex);
    *copy = text;
    return 0;
}

void sp_provenance_free(struct sp_provenance *p)
{
    free(p->scene);
    free(p->scene_file);
    free(p->command);
    p->scene = p->scene_file = p->command = NULL;
    for (int k = 0; k < p->n_more; k++) {
        free(p->more_files[k]);
        p->more_files[k] = NULL;
    }
    p->n_more = 0;
}

/* SP_E_INPUT (logged) when a scene's text is too long to record. */
static int check_length(size_t n)
{
    if (n >= SP_PROVENANCE_SCENE_MAX) {
        sp_log_error("the scene's text is %zu bytes; an output records at most %d (its "
                     "provenance): shorten the [timeline]'s captions or titles",
                     n, SP_PROVENANCE_SCENE_MAX - 1);
        return SP_E_INPUT;
    }
    return 0;
}

int sp_provenance_add_scene(struct sp_provenance *p, const struct sp_scene *scene)
{
    const int k = p->n_more;
    if (k >= SP_PROVENANCE_MAX_SCENES - 1) {
        sp_log_error("an output records at most %d scenes", SP_PROVENANCE_MAX_SCENES);
        return SP_E_INPUT;
    }
    char *text = sp_scene_ini(scene);
    if (!text) {
        sp_log_error("out of memory");
        return SP_E_NOMEM;
    }
    if (check_length(strlen(text))) {
        free(text);
        return SP_E_INPUT;
    }
    p->more_files[k] = text;
    snprintf(p->more_keys[k], sizeof(p->more_keys[k]), "%s.%d", SP_PROVENANCE_SCENE_FILE, k + 2);
    p->text[SP_PROVENANCE_N_TEXT + 1 + k] =
        (struct sp_png_text){.key = p->more_keys[k], .text = text, .compressed = 1};
    p->n_more = k + 1;
    return 0;
}

int sp_provenance_init(struct sp_provenance *p, const struct sp_scene *scene,
                       const char *renderer, const char *gl_version)
{
    p->scene = p->scene_file = p->command = NULL;
    p->n_more = 0;
    int ret = scene_sha256(scene, p->scene_sha256, &p->scene);
    if (ret)
        return ret;
    p->scene_file = sp_scene_ini(scene);
    if (!p->scene_file) {
        sp_log_error("out of memory");
        return SP_E_NOMEM;
    }
    size_t n = strlen(p->scene) > strlen(p->scene_file) ? strlen(p->scene) : strlen(p->scene_file);
    if (check_length(n))
        return SP_E_INPUT;
    snprintf(p->software, sizeof(p->software), "springpend " SP_VERSION);
    snprintf(p->renderer, sizeof(p->renderer), "%s", renderer ? renderer : "none");
    sp_provenance_set_time(p, 0);
    p->text[0] = (struct sp_png_text){.key = "Software", .text = p->software};
    p->text[1] = (struct sp_png_text){.key = "Source", .text = p->renderer};
    p->text[2] = (struct sp_png_text){.key = "springpend.scene-sha256", .text = p->scene_sha256};
    p->text[3] = (struct sp_png_text){.key = "springpend.time", .text = p->time};
    p->text[4] = (struct sp_png_text){.key = "springpend.scene", .text = p->scene, .compressed = 1};
    sp_environment_text(p->environment, sizeof(p->environment), renderer, gl_version);
    p->text[5] = (struct sp_png_text){.key = "springpend.environment", .text = p->environment,
                                      .compressed = 1};
    p->fonts[0] = 0;
    p->text[6] = (struct sp_png_text){.key = "springpend.fonts", .text = p->fonts};
    p->text[7] = (struct sp_png_text){.key = SP_PROVENANCE_SCENE_FILE, .text = p->scene_file,
                                      .compressed = 1};
    int n_words;
    sp_command_line_argv(&n_words);
    p->command = n_words ? sp_command_line_unnamed() : strdup("");
    if (!p->command) {
        sp_log_error("out of memory");
        return SP_E_NOMEM;
    }
    p->text[8] = (struct sp_png_text){.key = SP_PROVENANCE_COMMAND, .text = p->command};
    p->overlay[0] = 0;
    p->text[9] = (struct sp_png_text){.key = "springpend.overlay", .text = p->overlay};
    return 0;
}

int sp_provenance_set_command(struct sp_provenance *p, const char *command)
{
    char *copy = strdup(command ? command : "");
    if (!copy) {
        sp_log_error("out of memory");
        return SP_E_NOMEM;
    }
    free(p->command);
    p->command = copy;
    p->text[8].text = copy;
    return 0;
}

void sp_provenance_set_time(struct sp_provenance *p, double t)
{
    snprintf(p->time, sizeof(p->time), "%.9g", t);
}

int sp_provenance_scene_check(const char *path, const char *key, const char *text, size_t len)
{
    char origin[4200];
    struct sp_scene sc;
    snprintf(origin, sizeof(origin), "%s: %s", path, key);
    if (!len) {
        sp_log_error("%s: empty; an output of springpend records its scene there", origin);
        return SP_E_INPUT;
    }
    if (len >= SP_PROVENANCE_SCENE_MAX) {
        sp_log_error("%s: %zu bytes; springpend records at most %d", origin, len,
                     SP_PROVENANCE_SCENE_MAX - 1);
        return SP_E_INPUT;
    }
    if (strlen(text) != len) {
        sp_log_error("%s: a NUL byte at %zu; a scene holds none", origin, strlen(text));
        return SP_E_INPUT;
    }
    sp_scene_defaults(&sc);
    int ret = sp_scene_parse(&sc, text, origin, NULL, 0);
    char *again = ret ? NULL : sp_scene_ini(&sc);
    sp_scene_free(&sc);
    if (ret)
        return SP_E_INPUT; /* the parser said what and where */
    if (!again) {
        sp_log_error("out of memory");
        return SP_E_NOMEM;
    }
    if (strcmp(again, text)) {
        int line = 1;
        for (size_t i = 0; text[i] && text[i] == again[i]; i++)
            line += text[i] == '\n';
        sp_log_error("%s:%d: not as springpend writes the scene (its keys in order, under "
                     "their [section], one each); the record was edited or made elsewhere",
                     origin, line);
        ret = SP_E_INPUT;
    }
    free(again);
    return ret;
}
