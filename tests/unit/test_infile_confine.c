/* springpend tests: reads confined to a folder (infile.h, sp_infile_confine;
 * attack13 #23). A file a folder walk took that became a link out of its
 * folder afterwards is refused when it is opened, with a message naming it,
 * where it leads and the folder, never read; links within the folder are
 * followed (relative, through "../FOLDER/", absolute: the last refused by
 * openat2 RESOLVE_BENEATH and then checked by where the file lies); a FIFO
 * is still refused unopened; a path outside every confined folder, and
 * every path after sp_infile_confine_end, opens as before; the folder is
 * held by the descriptor taken when it was confined (the folder renamed
 * and a link to elsewhere put in its place changes nothing); a folder made
 * after it was confined (new baselines) is confined too.
 * All in a temporary folder (never /dev). usage: test_infile_confine */
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>
#if __has_include(<linux/openat2.h>)
#include <linux/openat2.h>
#endif

#include "springpend/common.h"
#include "springpend/infile.h"
#include "tap.h"

static char top[64];

/* top/name, in a rotating buffer. */
static const char *at(const char *name)
{
    static char buf[8][512];
    static int k;
    k = (k + 1) % 8;
    snprintf(buf[k], sizeof(buf[k]), "%s/%s", top, name);
    return buf[k];
}

static void put(const char *name, const char *text)
{
    FILE *fp = fopen(at(name), "w");
    if (fp) {
        fputs(text, fp);
        fclose(fp);
    }
}

/* What sp_infile_read gives for path ("" when refused), and what it said
 * on stderr into said (size bytes). Returns the read's status. */
static int read_said(const char *path, char *text, size_t size, char *said, size_t said_size)
{
    char log[600];
    snprintf(log, sizeof(log), "%s/log.txt", top);
    fflush(stderr);
    const int saved = dup(2), fd = open(log, O_WRONLY | O_CREAT | O_TRUNC, 0600);
    dup2(fd, 2);
    close(fd);
    char *got = NULL;
    size_t n = 0;
    const int ret = sp_infile_read(path, 1000, "want", &got, &n);
    fflush(stderr);
    dup2(saved, 2);
    close(saved);
    snprintf(text, size, "%s", got ? got : "");
    free(got);
    FILE *fp = fopen(log, "r");
    said[0] = 0;
    if (fp) {
        n = fread(said, 1, said_size - 1, fp);
        said[n] = 0;
        fclose(fp);
    }
    return ret;
}

/* 1 when path reads as want, nothing said. */
static int reads(const char *path, const char *want)
{
    char text[64], said[600];
    return read_said(path, text, sizeof(text), said, sizeof(said)) == 0 && !strcmp(text, want) &&
           !said[0];
}

/* 1 when path is refused as leading out of folder dir to where. */
static int escapes(const char *path, const char *where, const char *dir)
{
    char text[64], said[600], want[1400];
    const char *why = NULL;
    const int fd = sp_infile_try(path, &why);
    if (fd >= 0)
        close(fd);
    snprintf(want, sizeof(want), "springpend: %s changed after the folder was listed: it leads "
             "to %s, not inside %s: not read\n", path, where, dir);
    const int ret = read_said(path, text, sizeof(text), said, sizeof(said));
    if (strcmp(said, want))
        sp_tap_diag("said %s", said);
    return fd == SP_E_INPUT && why && strstr(why, "changed after the folder was listed") &&
           ret == SP_E_INPUT && !text[0] && !strcmp(said, want);
}

/* 1 when this kernel has openat2 (Linux 5.6) and lets this process call it. */
static int openat2_works(void)
{
#if defined(SYS_openat2) && defined(RESOLVE_BENEATH)
    struct open_how how = {.flags = O_PATH | O_CLOEXEC, .resolve = RESOLVE_BENEATH};
    const int fd = (int)syscall(SYS_openat2, AT_FDCWD, ".", &how, sizeof(how));
    if (fd >= 0)
        close(fd);
    return fd >= 0;
#else
    return 0;
#endif
}

int main(void)
{
    char real_top[4096], in[600];
    snprintf(top, sizeof(top), "/tmp/sp-confine-XXXXXX");
    if (!mkdtemp(top) || !realpath(top, real_top))
        return 99;
    snprintf(in, sizeof(in), "%s/in", top);
    mkdir(at("in"), 0700);
    mkdir(at("in/sub"), 0700);
    put("in/x.png", "inside");
    put("in/sub/y.png", "below");
    put("out.png", "outside");
    symlink("x.png", at("in/rel.png"));
    symlink("../in/x.png", at("in/up.png"));
    symlink("../x.png", at("in/sub/back.png"));
    symlink(at("in/x.png"), at("in/abs.png"));
    symlink("../out.png", at("in/esc.png"));
    symlink(at("out.png"), at("in/escabs.png"));
    symlink("loop.png", at("in/loop.png"));
    mkfifo(at("in/fifo.png"), 0600);

    sp_tap_ok(reads(at("in/esc.png"), "outside"), "unconfined, a link out is followed");
    sp_tap_ok(sp_infile_confine(in) == 0, "%s confined", in);
    const char *const within[] = {"in/x.png", "in/rel.png", "in/up.png", "in/abs.png",
                                  "in/sub/back.png"};
    for (size_t k = 0; k < sizeof(within) / sizeof(within[0]); k++)
        sp_tap_ok(reads(at(within[k]), "inside"), "%s: within, read", within[k]);
    sp_tap_ok(reads(at("in//sub/y.png"), "below"), "in//sub/y.png: a doubled '/' is the same");
    char out[4200];
    snprintf(out, sizeof(out), "%s/out.png", real_top);
    sp_tap_ok(escapes(at("in/esc.png"), out, in), "in/esc.png (../out.png): refused, said");
    sp_tap_ok(escapes(at("in/escabs.png"), out, in), "in/escabs.png (absolute): refused, said");
    char text[64], said[600];
    sp_tap_ok(read_said(at("in/fifo.png"), text, sizeof(text), said, sizeof(said)) ==
                  SP_E_INPUT && strstr(said, "is a FIFO, not a regular file"),
              "in/fifo.png: a FIFO, refused unopened (%s)", said);
    sp_tap_ok(read_said(at("in/loop.png"), text, sizeof(text), said, sizeof(said)) ==
                  SP_E_INPUT && strstr(said, "cannot open"), "in/loop.png: a loop, refused");
    sp_tap_ok(reads(at("out.png"), "outside"), "out.png, outside every confined folder: read");

    /* the file swapped for a link out after the walk: the finding */
    rename(at("in/x.png"), at("in/x.keep"));
    symlink(at("out.png"), at("in/x.png"));
    sp_tap_ok(escapes(at("in/x.png"), out, in), "in/x.png swapped for a link out: refused");
    sp_tap_ok(escapes(at("in/rel.png"), out, in), "in/rel.png, through it: refused");
    unlink(at("in/x.png"));
    rename(at("in/x.keep"), at("in/x.png"));

    /* the folder itself swapped for a link to the folder above */
    rename(at("in"), at("in.old"));
    symlink(".", at("in"));
    if (openat2_works())
        sp_tap_ok(reads(at("in/x.png"), "inside"), "the folder renamed, a link in its place: "
                  "its own x.png still read, through the descriptor taken when confined");
    else /* opened by name, kept where it lies in the folder's real path */
        sp_tap_ok(read_said(at("in/x.png"), text, sizeof(text), said, sizeof(said)) ==
                      SP_E_INPUT && !text[0], "the folder renamed, a link in its place, no "
                  "openat2 here: in/x.png (now top/x.png) not read");
    sp_tap_ok(read_said(at("in/out.png"), text, sizeof(text), said, sizeof(said)) ==
                  SP_E_INPUT && !text[0], "... and in/out.png (now top/out.png) not read");
    unlink(at("in"));
    rename(at("in.old"), at("in"));

    /* a folder that does not exist yet when confined */
    char made[600];
    snprintf(made, sizeof(made), "%s/new/", top);
    sp_tap_ok(sp_infile_confine(made) == 0, "%s (not there yet) confined", made);
    mkdir(at("new"), 0700);
    put("new/b.png", "new");
    symlink("../out.png", at("new/l.png"));
    sp_tap_ok(reads(at("new/b.png"), "new"), "new/b.png, made since: read");
    sp_tap_ok(escapes(at("new/l.png"), out, at("new")), "new/l.png, a link out: refused");

    sp_infile_confine_end();
    sp_tap_ok(reads(at("in/esc.png"), "outside"), "after sp_infile_confine_end, followed again");

    const char *const names[] = {"in/rel.png", "in/up.png", "in/abs.png", "in/sub/back.png",
                                 "in/esc.png", "in/escabs.png", "in/loop.png", "in/fifo.png",
                                 "in/x.png", "in/sub/y.png", "new/b.png", "new/l.png",
                                 "out.png", "log.txt"};
    for (size_t k = 0; k < sizeof(names) / sizeof(names[0]); k++)
        unlink(at(names[k]));
    rmdir(at("in/sub"));
    rmdir(at("in"));
    rmdir(at("new"));
    rmdir(top);
    return sp_tap_done();
}
