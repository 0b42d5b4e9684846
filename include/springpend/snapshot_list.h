/* springpend: what `compare EXPECTED ACTUAL` compares in folder mode. Both
 * folders are walked, subfolders too (names starting with '.' as well, to
 * SP_SNAPSHOT_MAX_DEPTH: deeper is an error), for PNGs and videos; a link
 * to a folder is not followed but listed as NAME/ (sp_snapshot_is_folder_link),
 * so that the run reports it; each image's baselines are
 * EXPECTED/NAME and its alternatives EXPECTED/STEM.KEY.EXT beside it (a
 * baseline per environment: `a.png`, `a.llvm19.png`), any of which may match.
 * A baseline is an alternative only when KEY is a declared environment key
 * (compare.ini's envs line); otherwise it is an image of its own
 * (`fig.1.png`). An alternative goes beside its plain baseline STEM.EXT:
 * one without it is an error (attack12 #15), as an actual image named like
 * an alternative is. */
#ifndef SPRINGPEND_SNAPSHOT_LIST_H
#define SPRINGPEND_SNAPSHOT_LIST_H

/* One image (or video) to compare. */
struct sp_snapshot {
    char *name;     /* relative path, '/' between folders ("sub/a.png"); owned */
    int expected;   /* 1: EXPECTED/name exists */
    int actual;     /* 1: ACTUAL/name exists */
    char **alts;    /* relative names of the alternatives, sorted; owned */
    int n_alts, cap_alts; /* in use, room for */
    int nested;     /* 1: name is NAME.KEY.KEY.EXT (a baseline only) whose stem
                       NAME.KEY.EXT is itself an alternative: an error, never
                       silently dropped */
    int alt_named;  /* 1: name is an actual image's named like an alternative
                       (NAME.KEY.EXT, KEY declared, whatever else exists),
                       which only --update --env KEY writes, to the
                       baselines: an error, never compared, added or made a
                       candidate (attack11 #11, attack12 #15) */
    int orphan;     /* 1: name is a baseline NAME.KEY.EXT (KEY declared) and
                       NAME.EXT is in neither folder: an alternative of
                       nothing, an error (attack12 #15) */
};

struct sp_snapshot_list {
    struct sp_snapshot *items; /* sorted by name; owned */
    int n;
};

/* Folders below EXPECTED or ACTUAL deeper than this are refused. */
#define SP_SNAPSHOT_MAX_DEPTH 64

/* 1 when name is a link to a folder that the walk listed but did not follow
 * (it ends in '/'). */
int sp_snapshot_is_folder_link(const char *name);

/* 1 when name ends in .png (any case). */
int sp_snapshot_is_png(const char *name);

/* 1 when name ends in an extension compare reads as a video, in folders
 * as alone (src/compare/video_names.h: .mp4, .m4v, .mov, .webm, .mkv,
 * .gif, .h264, .264, .hevc, .h265, .265). */
int sp_snapshot_is_video(const char *name);

/* Lists dir_e and dir_a (a missing dir_e lists as empty) into l, skipping
 * the folders in skip (n_skip paths, NULL entries ignored: where --diff and
 * --candidates write); keys (n_keys) are the declared environment keys of
 * alternatives (none: every file is an image of its own). Returns 0, SP_E_INPUT (a folder that cannot be read:
 * logged) or SP_E_NOMEM. */
int sp_snapshot_list_make(struct sp_snapshot_list *l, const char *dir_e, const char *dir_a,
                          const char *const *skip, int n_skip, const char *const *keys,
                          int n_keys);

/* The length of name's KEY when it is named like an alternative,
 * NAME.KEY.EXT with KEY one of keys (n_keys), whatever exists; then
 * NAME.EXT into stem (size bytes; stem may be NULL). 0 otherwise. */
int sp_snapshot_key_named(const char *name, const char *const *keys, int n_keys, char *stem,
                          int size);
/* The KEY of alternative alt of image name ("a.llvm19.png" of "a.png" is
 * "llvm19"), into key. */
void sp_snapshot_alt_key(const char *name, const char *alt, char *key, int size);

/* The name of image name's alternative for environment key ("a.png", "ci"
 * gives "a.ci.png"), into out. */
void sp_snapshot_alt_name(const char *name, const char *key, char *out, int size);

void sp_snapshot_list_free(struct sp_snapshot_list *l);

#endif
