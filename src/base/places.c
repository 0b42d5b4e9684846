/* springpend: where the running executable is and what is around it (see
 * places.h). */
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "places.h"

/* 1 when a and b name the same file or folder. */
static int same_file(const char *a, const char *b)
{
    struct stat sa, sb;
    return stat(a, &sa) == 0 && stat(b, &sb) == 0 && sa.st_dev == sb.st_dev &&
           sa.st_ino == sb.st_ino;
}

/* The running executable's folder into dir (PATH_MAX bytes); 0, or -1. */
static int exe_folder(char *dir)
{
    ssize_t n = readlink("/proc/self/exe", dir, PATH_MAX - 1);
    if (n <= 0)
        return -1;
    dir[n] = 0;
    char *slash = strrchr(dir, '/');
    if (!slash)
        return -1;
    *slash = 0;
    return 0;
}

/* The value of the line "key=..." of text into out (PATH_MAX bytes); 0, or -1. */
static int marker_line(const char *text, const char *key, char *out)
{
    size_t klen = strlen(key);
    for (const char *p = text; p && *p; p = strchr(p, '\n'), p = p ? p + 1 : NULL) {
        if (strncmp(p, key, klen) || p[klen] != '=')
            continue;
        const char *v = p + klen + 1, *end = strchr(v, '\n');
        size_t len = end ? (size_t)(end - v) : strlen(v);
        if (!len || len >= PATH_MAX)
            return -1;
        memcpy(out, v, len);
        out[len] = 0;
        return 0;
    }
    return -1;
}

/* 1 when folder holds SP_BUILD_MARK naming folder itself as the build tree
 * (build and source filled as sp_build_tree says). */
static int is_build_tree(const char *folder, char *build, char *source)
{
    char path[PATH_MAX + 64], text[2 * PATH_MAX + 512], b[PATH_MAX], s[PATH_MAX];
    snprintf(path, sizeof(path), "%s/%s", folder, SP_BUILD_MARK);
    FILE *f = fopen(path, "re");
    if (!f)
        return 0;
    size_t n = fread(text, 1, sizeof(text) - 1, f);
    fclose(f);
    text[n] = 0;
    if (marker_line(text, "build", b) || marker_line(text, "source", s) || !same_file(b, folder))
        return 0;
    if (build)
        snprintf(build, PATH_MAX, "%s", b);
    if (source)
        snprintf(source, PATH_MAX, "%s", s);
    return 1;
}

int sp_build_tree(char *build, char *source)
{
    char exe[PATH_MAX], up[PATH_MAX + 8];
    if (exe_folder(exe))
        return 0;
    for (int level = 0; level < 3; level++) {
        snprintf(up, sizeof(up), "%s%s", exe, level == 0 ? "" : level == 1 ? "/.." : "/../..");
        if (is_build_tree(up, build, source))
            return 1;
    }
    return 0;
}

/* 1 when path is a folder and (probe not NULL) holds the readable file
 * probe: a guides' folder that dpkg's path-exclude emptied but for its
 * copyright file is no guides' folder (attack19 #6). */
static int holds(const char *path, const char *probe)
{
    struct stat st;
    char file[2 * PATH_MAX + 128];
    if (stat(path, &st) != 0 || !S_ISDIR(st.st_mode))
        return 0;
    if (!probe)
        return 1;
    snprintf(file, sizeof(file), "%s/%s", path, probe);
    return stat(file, &st) == 0 && S_ISREG(st.st_mode) && access(file, R_OK) == 0;
}

/* The folder named sub in the source tree when run from a build tree; else
 * reldir from the executable's folder (an absolute reldir as it is), where
 * it is a folder (holding probe, unless NULL); else absdir. Resolved, into
 * dir. 0 when dir is such a folder, -1 when not (absdir, where nothing was
 * installed or it was removed). */
static int shipped_dir(char *dir, size_t size, const char *sub, const char *reldir,
                       const char *absdir, const char *probe)
{
    char exe[PATH_MAX], source[PATH_MAX], path[2 * PATH_MAX + 64], real[PATH_MAX];
    if (sp_build_tree(NULL, source))
        snprintf(path, sizeof(path), "%s/%s", source, sub);
    else if (exe_folder(exe) == 0 && reldir[0] != '/')
        snprintf(path, sizeof(path), "%s/%s", exe, reldir);
    else
        snprintf(path, sizeof(path), "%s", absdir);
    if (!holds(path, probe))
        snprintf(path, sizeof(path), "%s", absdir);
    snprintf(dir, size, "%s", realpath(path, real) ? real : path);
    return holds(dir, probe) ? 0 : -1;
}

void sp_scenes_dir(char *dir, size_t size)
{
    (void)shipped_dir(dir, size, "scenes", SP_SCENES_RELDIR, SP_SCENES_DIR, NULL);
}

int sp_docs_dir(char *dir, size_t size)
{
    /* outputs.md: the guide most --help texts point to */
    return shipped_dir(dir, size, "doc", SP_DOCS_RELDIR, SP_DOCS_DIR, "outputs.md");
}
