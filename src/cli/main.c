/* springpend: entry point. Dispatches to a command; the only place that
 * turns an SP_E_* code into an exit status. */
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <malloc.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "base/command_line.h"
#include "base/places.h"
#include "springpend/common.h"
#include "springpend/environment.h"
#include "springpend/infile.h"
#include "springpend/outfile.h"
#include "springpend/render.h"
#include "springpend/scene.h"
#include "base/signals.h"

static const char usage[] =
    "springpend " SP_VERSION " - renders the spring (elastic) pendulum, headless\n"
    "\n"
    "usage: springpend COMMAND SCENE [options]\n"
    "\n"
    "commands:\n"
    "  render   the whole motion as MP4, WebM, GIF, a PNG sequence or raw frames\n"
    "  still    one frame as a PNG, or an SVG or PDF vector figure\n"
    "  data     the motion as CSV: state, polar form, energies (no rendering)\n"
    "  info     the scene's frequencies, resonance, energies, and the step's margin\n"
    "  keys     list every scene key with its default and accepted range\n"
    "  scene    print the scene a PNG, video or CSV was made from, as a scene file\n"
    "  compare  compare PNG images, folders of them or videos (snapshot tests in CI)\n"
    "  sweep    many pendulums over a grid of keys: Lyapunov maps, orbit diagrams,\n"
    "           Poincare mosaics (PNG, SVG, PDF; sharded runs and their merge)\n"
    "  version  springpend's version (also --version); --verbose: the environment\n"
    "           a PNG records (renderer, libraries, fonts), for a bug report\n"
    "\n"
    "'springpend COMMAND --help' tells more. Scenes are INI files; the shipped\n"
    "ones, to start from (default.ini, chaotic.ini, ...), are in\n"
    "  %s/\n"
    "%s"
    "\n"
    "exit status: 0 done, 1 failed (I/O, encoder, GL; compare: images differ),\n"
    "             2 bad input, 3 the simulation became unstable,\n"
    "             128 + signal when stopped by SIGINT (130), SIGTERM (143),\n"
    "             SIGHUP (129), SIGQUIT (131), SIGUSR1/2 (138/140), SIGALRM (142),\n"
    "             SIGVTALRM (154), SIGXCPU (152), SIGPWR (158), SIGPROF (155),\n"
    "             SIGIO (157), SIGSTKFLT (144) or a real-time signal (162 to 192):\n"
    "             render keeps the frames so far, playable; other partial files\n"
    "             are removed (a signal ignored at the start, as under nohup,\n"
    "             stays ignored)\n";

static const char version_usage[] =
    "usage: springpend version [--verbose]\n"
    "\n"
    "Prints springpend's version ('springpend --version' is the same). With\n"
    "--verbose, the environment every PNG records, one 'key: value' line each:\n"
    "springpend, the GL renderer a render would use, Mesa and LLVM, the\n"
    "libraries and the fonts, for a bug report or a CI log.\n"
    "\n"
    "options:\n"
    "  --verbose              the environment, one 'key: value' line each\n"
    "  -h, --help             this text\n";

/* The process exit status of an SP_E_* code, as --help documents it. A
 * command that fails after a stop signal arrived was stopped by it (a read
 * cut by EINTR reports itself as bad input or I/O): 128 + the signal. */
static int exit_status(int err)
{
    if (err && sp_signal_seen())
        err = SP_E_INTERRUPTED;
    switch (err) {
    case SP_OK: return 0;
    case SP_E_INPUT: return 2;
    case SP_E_UNSTABLE: return 3;
    case SP_E_INTERRUPTED: {
        int sig = sp_signal_seen();
        return 128 + (sig ? sig : SIGINT);
    }
    default: return 1;
    }
}

/* What a command printed must have reached stdout: a full disk, a closed
 * pipe or /dev/full is a failure (exit 1) with a message, not a silent 0. */
static int stdout_checked(int err)
{
    if (fflush(stdout) == 0 && !ferror(stdout))
        return err;
    if (err == SP_OK || err == SP_E_MISMATCH)
        sp_log_error("cannot write to stdout: %s", errno == EPIPE
                     ? "the reader closed the pipe" : strerror(errno));
    return err ? err : SP_E_IO;
}

struct command {
    const char *name;
    int (*run)(int argc, char **argv, const volatile sig_atomic_t *cancel);
    int records; /* 1: its outputs record the command line (command_line.h) */
    int draws;   /* 1: it draws the scene's [view] (sp_scene_view_drawn) */
};

static int cmd_keys(int argc, char **argv, const volatile sig_atomic_t *cancel)
{
    (void)cancel;
    /* `--` ends the options, as for every command (POSIX: no operands
     * after it is fine); -h and --help before it print the keys too */
    for (int i = 1, options = 1; i < argc; i++)
        if (options && !strcmp(argv[i], "--")) {
            options = 0;
        } else if (!options || (strcmp(argv[i], "-h") && strcmp(argv[i], "--help"))) {
            sp_log_error("keys takes no arguments, not '%s'; see 'springpend --help'", argv[i]);
            return SP_E_INPUT;
        }
    printf("scene keys (SI units; angles in degrees):\n");
    sp_scene_print_keys();
    return 0;
}

static const struct command commands[] = {
    {"render", sp_cmd_render, 1, 1},
    {"still", sp_cmd_still, 1, 1},
    {"data", sp_cmd_data, 1, 0},
    {"info", sp_cmd_info, 0, 0},
    {"keys", cmd_keys, 0, 1},
    {"compare", sp_cmd_compare, 0, 1},
    {"sweep", sp_cmd_sweep, 1, 0},
    {"scene", sp_cmd_scene, 0, 0},
};

/* Fills a closed stdin, stdout or stderr with /dev/null opened the wrong way
 * round (reads and writes still fail, EBADF, as on a closed descriptor), so
 * that no file springpend opens becomes fd 0-2 and takes its messages
 * (attack20 #2: `data ... 2>&-` wrote its progress into the CSV). */
static void hold_standard_fds(void)
{
    for (int fd = 0; fd <= 2; fd++)
        if (fcntl(fd, F_GETFD) < 0 && errno == EBADF) {
            const int got = open("/dev/null", fd ? O_RDONLY : O_WRONLY);
            if (got >= 0 && got != fd) { /* a lower one was closed too: fill in order */
                dup2(got, fd);
                close(got);
            }
        }
}

int main(int argc, char **argv)
{
    hold_standard_fds();
    /* A closed pipe (e.g. `springpend render --format raw -o - | head -c 1`)
     * becomes a write error with a message instead of a silent death. */
    signal(SIGPIPE, SIG_IGN);
    sp_command_line_set(argc, argv); /* the provenance every output carries */
    sp_infile_stop_on(sp_signal_flag()); /* a read cut by a stop signal ends */
    if (argc < 2 || !strcmp(argv[1], "-h") || !strcmp(argv[1], "--help") ||
        !strcmp(argv[1], "help")) {
        char scenes[PATH_MAX], docs[PATH_MAX], guides[PATH_MAX + 160];
        sp_scenes_dir(scenes, sizeof(scenes));
        if (sp_docs_dir(docs, sizeof(docs)) == 0)
            snprintf(guides, sizeof(guides), "and the guides (scenes.md, outputs.md, ci.md, "
                     "teaching.md, ...) in\n  %s/\n", docs);
        else /* a system without /usr/share/doc */
            snprintf(guides, sizeof(guides), "and the guides (scenes.md, outputs.md, ci.md, "
                     "teaching.md, ...) are not\ninstalled here: they are doc/*.md in "
                     "springpend's source\n");
        fprintf(argc < 2 ? stderr : stdout, usage, scenes, guides);
        return argc < 2 ? 2 : exit_status(stdout_checked(0));
    }
    if (!strcmp(argv[1], "--version") || !strcmp(argv[1], "version")) {
        /* --verbose: the environment every PNG records (environment.h),
         * with the GL renderer a render would use. */
        if (argc > 2 && !strcmp(argv[2], "--verbose") && argc == 3) {
            char renderer[256], gl[256], env[SP_ENVIRONMENT_MAX];
            int glerr = sp_render_probe(SP_GL_DEFAULT, renderer, sizeof(renderer), gl,
                                        sizeof(gl));
            sp_environment_text(env, sizeof(env), glerr ? NULL : renderer, glerr ? NULL : gl);
            fputs(env, stdout);
            return exit_status(stdout_checked(0));
        }
        if (argc == 3 && (!strcmp(argv[2], "--help") || !strcmp(argv[2], "-h"))) {
            fputs(version_usage, stdout);
            return exit_status(stdout_checked(0));
        }
        if (argc > 2) {
            sp_log_error("%s: unknown option '%s'; expected nothing, --verbose or --help",
                         argv[1], argv[2]);
            return 2;
        }
        puts("springpend " SP_VERSION);
        return exit_status(stdout_checked(0));
    }
    /* Buffers of 256 KiB and more (frames) come from mmap and go back to
     * the system when freed. glibc would otherwise raise this threshold after
     * the first such free and serve them from the heap, where frames of
     * changing neighbours fragment it: a GIF's memory grew with its length. */
    mallopt(M_MMAP_THRESHOLD, 256 * 1024);
    /* A file size limit (ulimit -f) makes writes fail with EFBIG, reported
     * and cleaned up like any write error, instead of killing the process. */
    signal(SIGXFSZ, SIG_IGN);
    sp_signals_install();
    sp_outfile_set_cancel(sp_signal_flag()); /* a FIFO's wait stops on a signal */
    for (size_t i = 0; i < sizeof(commands) / sizeof(commands[0]); i++)
        if (!strcmp(argv[1], commands[i].name)) {
            /* a line no output could record whole, or springpend read
             * back, is refused before anything is computed */
            if (commands[i].records && sp_command_line_check(NULL))
                return 2;
            sp_scene_view_drawn(commands[i].draws);
            return exit_status(stdout_checked(commands[i].run(argc - 1, argv + 1, sp_signal_flag())));
        }
    sp_log_error("unknown command '%s'; see 'springpend --help'", argv[1]);
    return 2;
}
