/* springpend: option parsing shared by the scene commands. */
#include <errno.h>
#include <getopt.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cli.h"
#include "springpend/common.h"

static int add_override(struct sp_cli_options *o, const char *s)
{
    if (o->n_overrides >= SP_CLI_MAX_OVERRIDES) {
        sp_log_error("too many overrides; at most %d are allowed", SP_CLI_MAX_OVERRIDES);
        return SP_E_INPUT;
    }
    o->overrides[o->n_overrides++] = s;
    return 0;
}

int sp_cli_parse(struct sp_cli_options *o, int argc, char **argv, const char *usage,
                 int allow_at)
{
    static const struct option longopts[] = {
        {"output", required_argument, 0, 'o'}, {"set", required_argument, 0, 's'},
        {"size", required_argument, 0, 'S'},   {"fps", required_argument, 0, 'F'},
        {"at", required_argument, 0, 'a'},     {"quiet", no_argument, 0, 'q'},
        {"help", no_argument, 0, 'h'},         {"every", required_argument, 0, 'e'},
        {"scale", required_argument, 0, 'X'},
        {"state", required_argument, 0, 'J'},
        {0, 0, 0, 0},
    };
    int c, w, h, ret = 0;
    char tail;
    memset(o, 0, sizeof(*o));
    o->at = -1;
    o->every = -1;
    optind = 1;
    opterr = 0;
    while ((c = getopt_long(argc, argv, "o:qh", longopts, NULL)) != -1) {
        switch (c) {
        case 'o': o->output = optarg; break;
        case 's': ret = add_override(o, optarg); break;
        case 'q': o->quiet = 1; break;
        case 'h': fputs(usage, stdout); return 1;
        case 'S':
            if (sscanf(optarg, "%dx%d%c", &w, &h, &tail) != 2) {
                sp_log_error("--size %s: expected WIDTHxHEIGHT, e.g. --size 1920x1080", optarg);
                return SP_E_INPUT;
            }
            snprintf(o->size_buf[0], sizeof(o->size_buf[0]), "video.width=%d", w);
            snprintf(o->size_buf[1], sizeof(o->size_buf[1]), "video.height=%d", h);
            ret = add_override(o, o->size_buf[0]);
            if (!ret)
                ret = add_override(o, o->size_buf[1]);
            break;
        case 'F':
            snprintf(o->fps_buf, sizeof(o->fps_buf), "video.fps=%s", optarg);
            ret = add_override(o, o->fps_buf);
            break;
        case 'J':
            if (!(allow_at & SP_CLI_AT)) {
                sp_log_error("--state is for 'springpend still'; see '%s --help'", argv[0]);
                return SP_E_INPUT;
            }
            o->state = optarg;
            break;
        case 'a': {
            char *end;
            o->at = strtod(optarg, &end);
            if (!(allow_at & SP_CLI_AT) || end == optarg || *end || !(o->at >= 0) || o->at > 1e9) {
                sp_log_error("--at %s: expected a simulated time in seconds, 0 <= t <= 1e9",
                             optarg);
                return SP_E_INPUT;
            }
            break;
        }
        case 'X': {
            char *end;
            const long v = strtol(optarg, &end, 10);
            if (!(allow_at & SP_CLI_AT) || end == optarg || *end || v < 1 || v > 4) {
                sp_log_error("--scale %s: expected a supersampling factor from 1 to 4 "
                             "(still only)", optarg);
                return SP_E_INPUT;
            }
            o->scale = (int)v;
            break;
        }
        case 'e': {
            char *end;
            o->every = strtod(optarg, &end);
            if (!(allow_at & SP_CLI_EVERY) || end == optarg || *end || !(o->every > 0) ||
                o->every > 1e9) {
                sp_log_error("--every %s: expected a sampling interval in simulated "
                             "seconds, 0 < every <= 1e9", optarg);
                return SP_E_INPUT;
            }
            break;
        }
        default:
            sp_log_error("unknown option '%s'; see '%s --help'", argv[optind - 1], argv[0]);
            return SP_E_INPUT;
        }
        if (ret)
            return ret;
    }
    if (optind != argc - 1) {
        sp_log_error(optind >= argc ? "missing SCENE file; see '%s --help'"
                                    : "expected one SCENE file; see '%s --help'", argv[0]);
        return SP_E_INPUT;
    }
    o->scene_path = argv[optind];
    return 0;
}

int sp_cli_load_scene(const struct sp_cli_options *o, struct sp_scene *scene)
{
    sp_scene_defaults(scene);
    return sp_scene_load(scene, o->scene_path, o->overrides, o->n_overrides);
}

int sp_cli_same_file(const char *a, const char *b)
{
    struct stat sa, sb;
    return stat(a, &sa) == 0 && stat(b, &sb) == 0 && sa.st_dev == sb.st_dev &&
           sa.st_ino == sb.st_ino;
}

int sp_cli_check_writable(const char *path, const char *what)
{
    char dir[PATH_MAX];
    struct stat st;
    if (stat(path, &st) == 0 && S_ISDIR(st.st_mode)) {
        sp_log_error("%s %s is a folder; give a file name", what, path);
        return SP_E_INPUT;
    }
    /* The nearest ancestor that exists must be a folder we may write in;
     * the sink creates the missing ones below it. */
    snprintf(dir, sizeof(dir), "%s", path);
    for (;;) {
        char *slash = strrchr(dir, '/');
        if (!slash) {
            snprintf(dir, sizeof(dir), ".");
            break;
        }
        *slash = 0;
        if (slash == dir)
            snprintf(dir, sizeof(dir), "/");
        if (!dir[0] || stat(dir, &st) == 0 || (errno != ENOENT && errno != ENOTDIR))
            break;
    }
    if (stat(dir, &st) != 0 || !S_ISDIR(st.st_mode)) {
        sp_log_error("%s %s: %s is not a folder", what, path, dir);
        return SP_E_INPUT;
    }
    if (access(dir, W_OK | X_OK) != 0) {
        sp_log_error("%s %s: cannot write in folder %s: %s", what, path, dir, strerror(errno));
        return SP_E_INPUT;
    }
    return 0;
}

int sp_cli_output_path(const struct sp_cli_options *o, const struct sp_scene *scene,
                       const char *ext, char *buf, size_t size)
{
    if (o->output)
        snprintf(buf, size, "%s", o->output);
    else
        snprintf(buf, size, "out/%s%s", scene->name, ext);
    if (sp_cli_same_file(buf, o->scene_path)) {
        sp_log_error("output %s is the scene file itself; choose another -o", buf);
        return SP_E_INPUT;
    }
    return sp_cli_check_writable(buf, "output");
}
