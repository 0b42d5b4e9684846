/* springpend: per-image tolerances and masks for `springpend compare`, in a
 * file named compare.ini beside the baselines (the EXPECTED folder, or the
 * expected image's or video's folder), sections naming the baseline's file
 * name. Same INI syntax as scenes:
 *
 *     [*]                   # every image
 *     max_diff = 4
 *     [hud.png]             # one image (its file name)
 *     max_pixels = 0.5%
 *     mask = 0, 0, 200, 30  # x, y, width, height in px; repeat for more
 *     metric = rms
 *     tol = 1.5
 *
 * Keys: metric (reftest, rms or pixelmatch), threshold (pixelmatch's, 0..1), max_diff (0..255 levels), max_pixels (a
 * count up to 1e18, or P% with 0 <= P <= 100), tol (rms levels 0..255),
 * mask (integers, 0..1e9). Numbers are decimal: no hex, inf or nan. A [file]
 * section overrides wildcard sections ([hud-*.png]), which override [*]; an option on the command line is a limit neither
 * loosens. */
#ifndef SPRINGPEND_COMPARE_CONFIG_H
#define SPRINGPEND_COMPARE_CONFIG_H

#include <stddef.h>

#include "springpend/image_compare.h"

#define SP_COMPARE_CONFIG_NAME "compare.ini"
#define SP_COMPARE_MAX_MASKS 32

/* The options a command line or a section set. */
struct sp_compare_rule {
    char name[256];              /* section: a file name, or "*" */
    int line;                    /* of the [section] header */
    struct sp_compare_opts opts; /* the fields set below */
    unsigned set;                /* SP_COMPARE_SET_* bits */
    struct sp_compare_mask masks[SP_COMPARE_MAX_MASKS];
    int n_masks;
    int used;                    /* a compared image matched it */
};

#define SP_COMPARE_SET_METRIC 1u
#define SP_COMPARE_SET_MAX_DIFF 2u
#define SP_COMPARE_SET_MAX_PIXELS 4u
#define SP_COMPARE_SET_TOL 8u
#define SP_COMPARE_SET_THRESHOLD 16u

/* The most environment keys compare.ini's `envs` line declares. */
#define SP_COMPARE_MAX_ENVS 32
struct sp_compare_config {
    char path[4096];               /* "" when there was no file */
    struct sp_compare_rule *rules; /* owned */
    int n_rules, cap_rules;        /* in use, room for */
    /* The environment keys declared by `envs = KEY, KEY...` at the top of
     * the file (before any section): only NAME.KEY.EXT with one of these
     * is an alternative baseline of NAME.EXT, and --env names one. */
    char envs[SP_COMPARE_MAX_ENVS][33];
    int n_envs;
    int envs_line; /* of the envs line; 0 when there is none */
};
/* NULL when key can name an environment (1 to 32 letters, digits, '_' or
 * '-', and not a name compare gives files: diff, png or a video's
 * extension), else what is wrong with it. */
const char *sp_compare_env_key_check(const char *key);
/* 1 when cfg's envs line declares key. */
int sp_compare_config_has_env(const struct sp_compare_config *cfg, const char *key);

/* Parses one option into rule (name without "--": metric, max-diff or
 * max_diff, max-pixels or max_pixels, tol, mask). Returns 0, or
 * SP_E_INPUT with "NAME VALUE: what is wrong; expected what is allowed" in
 * why. */
int sp_compare_rule_set(struct sp_compare_rule *rule, const char *name, const char *value,
                        char *why, size_t why_size);

/* 1 when path is a symbolic link whose file (resolved, or not resolvable:
 * a loop, a dangling link) lies outside folder dir, or when a folder on the
 * way from dir to path is a link out of dir (path need not exist: its
 * nearest existing folder is checked); then `to` holds where it points
 * (size bytes). 0 for anything else, links within dir too, and when dir
 * does not exist.
 * compare reads nothing through such a link: a file in a pull request
 * could point at a secret (--report, compare.ini's messages) or at a file
 * --update would replace. */
int sp_compare_link_outside(const char *path, const char *dir, char *to, size_t size);

/* The folder half of sp_compare_link_outside: 1 when a folder on the way
 * from dir to path is a link out of dir (path itself may be a link: a
 * writer with SP_OUTFILE_REPLACE_LINK replaces it). */
int sp_compare_parent_outside(const char *path, const char *dir, char *to, size_t size);

/* 1 when path, made or not yet (its nearest existing folder stands for it;
 * a name alone that does not exist, for the working folder), is folder dir
 * or lies below it, links resolved; 0 when dir does not exist. compare
 * refuses folders that lie in each other, and outputs in the baselines. */
int sp_compare_folder_within(const char *path, const char *dir);

/* Reads dir/compare.ini into cfg when it exists (cfg stays empty when it
 * does not). Errors are printed as FILE:LINE: what is wrong, what is
 * allowed; returns 0, SP_E_INPUT or SP_E_NOMEM. A compare.ini that links
 * out of dir is refused (SP_E_INPUT). */
int sp_compare_config_load(struct sp_compare_config *cfg, const char *dir);

/* The most masks one image collects from the sections it matches. */
#define SP_COMPARE_RESOLVED_MASKS (4 * SP_COMPARE_MAX_MASKS)

/* The options and masks for image `name` (its path relative to the
 * baselines' folder, "sub/a.png"): the defaults, then [*], then every
 * section with a wildcard (fnmatch: * ? [..]) that matches, in file order,
 * then [name]; a section without '/' matches the file name in any folder, one
 * with '/' the relative path. Then the command line's rule `cli` as a limit:
 * each option it set is kept where compare.ini's is looser (the stricter of
 * the two applies; its metric is the metric), and when it sets a limit, its
 * own rule (its limits and the defaults, never compare.ini's fields) goes
 * into opts->also and opts->own, so the command line can tighten
 * compare.ini but never loosen it. The masks of every matching
 * section go into masks (at most SP_COMPARE_RESOLVED_MASKS; n_masks). Safe
 * to call from several threads at once. */
void sp_compare_config_resolve(struct sp_compare_config *cfg, const char *name,
                               const struct sp_compare_rule *cli,
                               struct sp_compare_opts *opts,
                               struct sp_compare_mask masks[SP_COMPARE_RESOLVED_MASKS],
                               int *n_masks);

/* Warns (stderr, FILE:LINE) about [file] sections that matched no image:
 * a misspelt name would otherwise be ignored in silence. */
void sp_compare_config_warn_unused(const struct sp_compare_config *cfg);

void sp_compare_config_free(struct sp_compare_config *cfg);

#endif
