/* springpend (internal): where the running executable is, and the places
 * around it that it names or loads from (places.c): the build tree it was
 * built in, when it runs from there, and the shipped scenes' and guides'
 * folders. No
 * absolute build path is compiled in (a package built in two folders is the
 * same package): the build tree is recognised at run time by the file
 * meson writes at its root (SP_BUILD_MARK, from src/base/build-tree.in).
 * Shared with: every folder. */
#ifndef SPRINGPEND_PLACES_H
#define SPRINGPEND_PLACES_H

#include <stddef.h>

/* 1 when the running executable (/proc/self/exe) is in a build tree: its
 * folder, or one or two folders up (tests/, tests/unit/), holds the file
 * SP_BUILD_MARK whose build= line names that very folder (a copied tree
 * or a lone marker is not one). Then the build folder goes to build and the
 * source folder to source, each PATH_MAX bytes (either may be NULL). Else 0. */
int sp_build_tree(char *build, char *source);

/* The folder of the shipped scenes (scenes/default.ini, ...), resolved (no
 * "..", no trailing slash), into dir: the source tree's scenes/ when run
 * from a build tree; else the installed one, found from the executable
 * (SP_SCENES_RELDIR: a moved or DESTDIR install too), else the configured
 * SP_SCENES_DIR. For messages, --help and a scene named without a folder. */
void sp_scenes_dir(char *dir, size_t size);

/* The folder of the guides (outputs.md, ci.md, ...; README.md beside them
 * when installed), found as sp_scenes_dir finds the scenes: the source
 * tree's doc/ from a build tree, else the installed one (SP_DOCS_RELDIR
 * from the executable, else SP_DOCS_DIR). For --help's pointers. 0, or -1
 * when no such folder holds outputs.md (a system that drops /usr/share/doc,
 * or keeps only its copyright files there). */
int sp_docs_dir(char *dir, size_t size);

#endif
