/* springpend fuzzing: the scene parser and validation (sp_scene_parse) on
 * arbitrary text plus --set overrides. The input is split at NUL bytes: the
 * first piece is the scene text, each further piece one override (at most
 * SP_CLI_MAX_OVERRIDES, as on the command line). No I/O but the parser's
 * messages on stderr (silence them with libFuzzer's -close_fd_mask=2).
 *
 * Built two ways (tests/fuzz/meson.build): with libFuzzer (-Dfuzz=enabled,
 * clang) for fuzzing, and with replay.c as a plain test that runs the seed
 * corpus and every past crash (tests/fuzz/regressions) in every build. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "springpend/common.h"
#include "springpend/scene.h"

/* An invariant of an accepted scene is broken: a bug, so crash loudly. */
#define CHECK(cond)                                                              \
    do {                                                                         \
        if (!(cond)) {                                                           \
            fprintf(stderr, "fuzz_scene: invariant failed: %s\n", #cond);        \
            abort();                                                             \
        }                                                                        \
    } while (0)

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* What validation promises about a scene it accepted. */
static void check_accepted(const struct sp_scene *s)
{
    const double reals[] = {
        s->pendulum.natural_length, s->pendulum.stiffness, s->pendulum.mass,
        s->pendulum.gravity, s->pendulum.damping, s->initial.length, s->initial.angle,
        s->initial.length_rate, s->initial.angle_rate, s->integrator.dt, s->video.fps,
        s->video.duration, s->video.speed,
    };
    for (size_t i = 0; i < sizeof(reals) / sizeof(reals[0]); i++)
        CHECK(isfinite(reals[i]));
    CHECK(s->pendulum.natural_length > 0 && s->pendulum.stiffness > 0 && s->pendulum.mass > 0);
    CHECK(s->pendulum.gravity >= 0 && s->pendulum.damping >= 0 && s->initial.length > 0);
    /* what the simulation derives stays finite (k/m, b/m, the static stretch) */
    CHECK(isfinite(s->pendulum.stiffness / s->pendulum.mass) &&
          isfinite(s->pendulum.damping / s->pendulum.mass) &&
          isfinite(s->pendulum.mass * s->pendulum.gravity / s->pendulum.stiffness));
    CHECK(s->integrator.dt > 0 && s->integrator.dt <= 1);
    CHECK(s->video.width >= 16 && s->video.height >= 16 &&
          (long)s->video.width * s->video.height <= 7680L * 4320L);
    CHECK(s->video.fps > 0 && s->video.duration > 0 && s->video.speed > 0);
    int n = sp_scene_frame_count(s);
    CHECK(n >= 1 && n <= 1000000000);
    CHECK(isfinite(sp_scene_frame_time(s, n - 1)) && sp_scene_frame_time(s, n - 1) >= 0);
    if (s->integrator.method <= SP_METHOD_YOSHIDA4) /* fixed steps */
        CHECK(s->video.duration / s->integrator.dt <= 1e10);
    if (s->integrator.method == SP_METHOD_RKN1210)
        CHECK(s->pendulum.damping == 0 && !(s->pivot.amplitude > 0 && s->pivot.frequency > 0));
    CHECK(s->integrator.tolerance >= 1e-15 && s->integrator.tolerance <= 1e-2);
    CHECK(isfinite(s->pivot.amplitude) && isfinite(s->pivot.frequency));
    CHECK(isfinite(s->view.strobe) && s->view.strobe >= 0);
    CHECK((s->view.trail >= 0 && s->view.trail <= 1000000) || s->view.trail == SP_TRAIL_ALL ||
          (s->view.trail == SP_TRAIL_DURATION && s->view.trail_duration > 0 &&
           s->view.trail_duration <= 1e6));
    CHECK(s->view.font_scale >= 0.25 && s->view.font_scale <= 4);
    /* title and caption: in the scene's own heap blocks, after where they
     * were set ("FILE:LINE" or "--set view.KEY"), or "" */
    const char *text[2] = {s->view.title, s->view.caption};
    const char *where[2] = {s->view.title_where, s->view.caption_where};
    for (int i = 0; i < 2; i++)
        CHECK(text[i] && where[i] &&
              (text[i][0] ? where[i] == s->texts[i] && where[i][0] &&
                            text[i] == where[i] + strlen(where[i]) + 1
                          : !s->texts[i] && !where[i][0]));
    CHECK(s->name[sizeof(s->name) - 1] == 0);
    CHECK(s->ensemble.count >= 0 && s->ensemble.count <= 10000);
    CHECK(s->ensemble.spread > 0 && s->ensemble.spread <= 1e12);
    CHECK(memchr(s->ensemble.key, 0, sizeof(s->ensemble.key)));
    if (s->ensemble.count > 1) /* a numeric key, whose both ends the parser accepted */
        CHECK(sp_scene_key_unit(s->ensemble.key) != NULL);
    const int len = sp_scene_canonical(s, NULL, 0); /* any length: the texts have no limit */
    char *buf = malloc((size_t)len + 1);
    CHECK(buf && len > 0 && sp_scene_canonical(s, buf, (size_t)len + 1) == len &&
          (int)strlen(buf) == len);
    free(buf);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *overrides[SP_CLI_MAX_OVERRIDES];
    int n = 0;
    char *text = malloc(size + 1);
    if (!text)
        return 0;
    memcpy(text, data, size);
    text[size] = 0;
    for (char *p = text + strlen(text); p < text + size && n < SP_CLI_MAX_OVERRIDES;
         p += strlen(p))
        overrides[n++] = ++p;

    struct sp_scene s;
    sp_scene_defaults(&s);
    snprintf(s.name, sizeof(s.name), "fuzz");
    int ret = sp_scene_parse(&s, text, "fuzz.ini", overrides, n);
    CHECK(ret == 0 || ret == SP_E_INPUT);
    if (ret == 0)
        check_accepted(&s);
    sp_scene_free(&s); /* the [timeline]'s cues and plan, whatever parse returned */
    free(text);
    return 0;
}
