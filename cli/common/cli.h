/* SPDX-License-Identifier: MIT */
/*
** cli.h -- the ggrt command line: subcommands and the helpers they share.
** The CLI uses only the public API (<ggrt.h>); option parsing is args.h.
*/
#ifndef GG_CLI_H
#define GG_CLI_H

#include "ggrt.h"
#include "common/args.h"

#include <stdio.h>

/* Exit codes (documented in ggrt(1)). A command cancelled by SIGINT,
   SIGTERM or SIGHUP dies of that signal after cleaning up (a shell shows
   128 + the signal number, e.g. 130). */
#define EXIT_OK    0
#define EXIT_USAGE 1
#define EXIT_INPUT 2
#define EXIT_IO    3
#define EXIT_CHECK 4 /* check, optics check: what was checked failed */

/* Each subcommand: argv[0] is the subcommand's name. */
int cmd_optics(int argc, char **argv);
int cmd_render(int argc, char **argv);
int cmd_merge(int argc, char **argv);
int cmd_plan(int argc, char **argv);
int cmd_trace(int argc, char **argv);
int cmd_info(int argc, char **argv);
int cmd_find(int argc, char **argv);
int cmd_check(int argc, char **argv);
int cmd_diff(int argc, char **argv);
int cmd_bench(int argc, char **argv);
int cmd_serve(int argc, char **argv);

/* The one map from a library status to an exit code: GG_ERROR_IO is 3,
   everything else bad input (2) -- except GG_ERROR_INVALID from a call
   whose only caller-chosen inputs are command-line values (from_args: the
   options and pixel given to ggRender or ggTracePixel), which is a usage
   error (1). */
int cli_exit_code(int status, int from_args);
/* Messages, one prefix rule: every error and warning on stderr starts
   "ggrt CMD: " (CMD as in "ggrt render: scene.nff:12:5: ..." or "ggrt
   optics refract: ..."; just "ggrt: " before a command is known).
   cli_parse calls cli_set_command with its command's name; cli_error
   prints "ggrt CMD: <message>", cli_warn "ggrt CMD: warning: <message>". */
void cli_set_command(const char *name);
/* "(see 'ggrt CMD --help')" on stderr, after a usage error's message. */
void cli_usage_hint(void);
void cli_error(const char *fmt, ...) CLI_PRINTF(1, 2);
void cli_warn(const char *fmt, ...) CLI_PRINTF(1, 2);
/* cli_error under the name of command cmd, for helpers that are told
   which command they serve ("trace", or "bench accuracy"). */
void cli_error_in(const char *cmd, const char *fmt, ...) CLI_PRINTF(2, 3);
/* cli_error(err->message), without a leading library function name
   ("ggDiff: "), then for a usage error the --help hint; returns
   cli_exit_code(status, from_args). */
int cli_fail(int status, const ggError *err, int from_args);

/* Seconds on the monotonic clock (for durations only). */
double cli_now(void);

/* Before a command spends time producing `path`: refuse a path that is a
   symbolic link, a directory or another non-regular file, or a read-only
   file, saying why on stderr ("ggrt CMD: ..."). Returns 0, EXIT_IO, or
   EXIT_USAGE for "-" (which would be a file of that name, not stdout). */
int cli_check_output(const char *cmd, const char *path);

/* The image format ggImageWrite picks from an output's extension: .png or
   .PNG, .exr or .EXR; CLI_IMAGE_NONE for anything else. */
enum { CLI_IMAGE_NONE = 0, CLI_IMAGE_PNG, CLI_IMAGE_EXR };
int cli_image_kind(const char *path);
/* For a parser: refuse an image output with another extension now, not
   after the work (a usage error: "WHAT must end in .png or .exr: 'PATH'").
   Returns CLI_GO or EXIT_USAGE. */
int cli_check_image_name(const cli_cmd *cmd, const char *what, const char *path);

/* For a parser: refuse an output (named by option opt, "-o") that is the
   same file as one of the n inputs (st_dev and st_ino, when both exist),
   which writing it would destroy. Returns CLI_GO or EXIT_USAGE. */
int cli_check_not_input(const cli_cmd *cmd, const char *opt, const char *out,
                        const char *const *inputs, int n);

/* For a parser: refuse two outputs of one command that are one file (by
   st_dev and st_ino when it exists, else by the real path of its folder
   and its name): one would overwrite the other, or the second write fail
   after the work. opts[i] names the option of paths[i]; NULL paths are
   skipped. Returns CLI_GO or EXIT_USAGE. */
int cli_check_distinct(const cli_cmd *cmd, const char *const *opts, const char *const *paths,
                       int n);
/* Are p and q one file, by cli_check_distinct's test? (NULL: no.) */
int cli_same_file(const char *p, const char *q);
/* Once the scene is loaded: refuse an output (opts[i] names the option
   of outs[i]; NULL outs skipped) that is one of the files the scene was
   read from (ggSceneInputFile: a mesh, MTL or texture file besides the
   scene), by cli_same_file. 0, or EXIT_USAGE after saying which. */
int cli_check_not_read(const char *cmd, const ggScene *s, const char *const *opts,
                       const char *const *outs, int n);

/* The longest path an output may have (Linux's PATH_MAX). */
#define CLI_PATH_MAX 4096

/* A text output file written whole or not at all: cli_out_open creates a
   new file beside it (at most 200 bytes of its name, ".tmp", the process
   id and the clock, tried again if taken; the replaced file's mode);
   cli_out_close flushes, fsyncs and renames it over path, or removes it on
   any error. Both print the reason ("ggrt CMD: x.svg: No space left on
   device") and return 0 / EXIT_IO. */
typedef struct cli_out {
    FILE *f;
    char path[CLI_PATH_MAX], tmp[CLI_PATH_MAX + 64];
} cli_out;
int cli_out_open(cli_out *o, const char *cmd, const char *path);
int cli_out_close(cli_out *o, const char *cmd);
/* Give up an open cli_out: close it and remove its temporary file (path
   stays as it was). For a write a cancel signal stopped. */
void cli_out_abandon(cli_out *o);

/* The triangles of a scene's implicit surfaces, all of them together,
   where ggrt draws them for a person to look at: ggrt serve's 3D view at
   most CLI_SURFACE_TRIANGLES (a page the browser draws at once), ggrt
   trace --scene-obj at most CLI_SCENE_OBJ_TRIANGLES (a file for Blender
   or MeshLab: about 20 MB; one surface at 64 cells takes 10k to 100k
   triangles, a rough one over a million). Each writes a surface coarser,
   or leaves it out, rather than go over. */
#define CLI_SURFACE_TRIANGLES   100000L
#define CLI_SCENE_OBJ_TRIANGLES (5 * CLI_SURFACE_TRIANGLES)
/* The grids both try, finest first (cells along the box's longest side),
   until a surface's triangles fit (common/scene.c). */
#define CLI_SURFACE_STEPS 7
extern const int cli_surface_cells[CLI_SURFACE_STEPS];

/* The whole file at path, NUL-terminated, in malloc'd memory sized as it
   is read, if it holds at most max bytes: returns 0 with *text (the
   caller frees it) and *len; else CLI_READ_IO (errno says why: it
   cannot be opened or read), CLI_READ_NOTFILE (a FIFO, device or
   directory: refused at once, never waited on, as the library refuses
   them), CLI_READ_LARGE (more than max bytes) or CLI_READ_NOMEM, and
   *text is NULL. The caller prints the reason. */
enum { CLI_READ_IO = 1, CLI_READ_LARGE, CLI_READ_NOMEM, CLI_READ_NOTFILE };
int cli_read_text(const char *path, size_t max, char **text, size_t *len);

/* c as "R G B", each "%.<prec>g" but every NaN "nan" (glibc prints a
   negative one "-nan"; the JSON and the page say "nan"), into buf;
   returns buf. One spelling of a pixel in every command's text. */
#define CLI_COLOR_LEN 80
const char *cli_color(char *buf, size_t size, int prec, ggColor c);

/* The shortest "%.Ng" (N = 1..17) of d that reads back as d, into buf:
   0.1, not 0.10000000000000001, in messages and manifests. */
void cli_shortest(char *buf, size_t size, double d);

/* Print " ARG", quoted for a POSIX shell when it needs quoting, so that a
   printed command line works when pasted. */
void cli_print_arg(FILE *f, const char *arg);
/* The same for a file name: one that starts with '-' as "./-x.nff", so
   that the command line does not read it as options. */
void cli_print_file(FILE *f, const char *path);

/* Cancellation by SIGINT, SIGTERM and SIGHUP (signals ignored when ggrt
   started stay ignored). cli_cancel_begin installs the handlers: from
   then on a signal only sets a flag, which cli_cancelled returns (the
   signal number, or 0); a progress callback returns it to stop the
   render. cli_cancel_hold blocks the signals (around a write that must
   finish or fail whole) and cli_cancel_release unblocks them.
   cli_cancel_exit restores the default action and re-raises the signal:
   the process dies of it, as a shell expects. */
void cli_cancel_begin(void);
int cli_cancelled(void);
void cli_cancel_hold(void);
void cli_cancel_release(void);
void cli_cancel_exit(int signo);
/* Between a finished write of `path` and cli_cancel_release: if a cancel
   signal came during the write, say that the file was written whole
   (the process dies of the signal next, and a scheduler will count the
   job as failed). */
void cli_cancel_after_write(const char *path);

/* The progress bar of every long command (common/cancel.c): on a
   terminal, unless quiet, "LABEL [####....]  42%  1.3s  ~2s left" redrawn
   on stderr as the work goes; cli_bar_step is a ggProgressFn (ud: the
   cli_bar) that also returns 1 once a cancel signal came, so the library
   stops. cli_bar_end ends the line the bar drew, if it drew one. A bar
   whose `after` is set (seconds; cli_bar_begin sets cli_bar_delay(0))
   draws nothing until the work has taken that long: a step that is
   usually quick (loading a scene) shows a bar only when it is not.
   cli_bar_delay gives GGRT_PROGRESS_DELAY's seconds where the environment
   sets it, else dflt (a value that is not a number of seconds is ignored,
   with one warning). */
typedef struct cli_bar {
    const char *label; /* "" for none */
    double t0, after;
    int last_pct, draw;
} cli_bar;
double cli_bar_delay(double dflt);
void cli_bar_begin(cli_bar *b, const char *label, int quiet);
int cli_bar_step(void *ud, long done, long total);
void cli_bar_end(cli_bar *b);

/* Load a scene file and prepare it (common/scene.c): how every command
   that takes a scene loads it. `loaded` (may be NULL) is called with ud
   between the two, on the scene as read (ggrt render prints a model's
   view and warnings there). Unless quiet, a step that takes over half a
   second shows a bar ("loading", "preparing"; cli_bar). On failure
   prints why ("ggrt CMD: file:line: ...") and returns NULL with the exit
   code in *rc (cli_exit_code); else *rc is EXIT_OK. */
typedef void (*cli_loaded_fn)(ggScene *s, const char *path, void *ud);
ggScene *cli_load_scene(const char *path, cli_loaded_fn loaded, void *ud, int quiet, int *rc);

/* Meshes (common/scene.c): does the path name a model (.obj, .ply) that
   ggSceneLoadFile frames; each mesh's description (ggrt info); a warning
   (cli_warn) per mesh that has any; a framed model's camera and lights as NFF; and
   "triangle T: face F of FILE (line L), group 'G', usemtl 'M'" for a hit
   (returns 0 when the object is not a mesh). */
int cli_is_model(const char *path);
void cli_print_meshes(FILE *f, const ggScene *s);
void cli_print_mesh_warnings(const ggScene *s);
void cli_print_model_view(FILE *f, const ggScene *s, const char *path);
int cli_face_text(const ggScene *s, int object, long triangle, char *buf, size_t n);

/* The most bytes one pixel's recorded trees can take under o (find, check,
   diff, trace record them; each tracing thread holds one pixel's, a diff
   two): every eye ray of the pixel, each with at most 1 + the ray budget
   rays -- fewer when the depth is set: at most as many children a hit as
   the scene's effects allow (a reflection, and a refraction or three
   dispersed ones: 0, 1, 2 or 4) -- each ray a node and a light record
   per light. An upper bound, not an estimate. */
double cli_record_bytes(const ggScene *s, const ggRenderOptions *o);
/* Refuse, before the work, options whose trees (threads x sides pixels
   at once, threads 0: one per core) could take more than half of this machine's
   memory: 0, or EXIT_USAGE after saying so ("ggrt CMD: the ray trees of
   one pixel could take ..."). */
int cli_check_recordable(const char *cmd, const ggScene *s, const ggRenderOptions *o, int threads,
                         int sides);
/* The two sides of a diff (diff, trace --diff) must be images of one
   size: the same pixel of two sizes is not the same ray. 0, or
   EXIT_USAGE after saying so and what to give (a size of 0 in an options
   struct is its scene's camera's). */
int cli_check_same_size(const char *cmd, const ggScene *sa, const ggRenderOptions *oa,
                        const ggScene *sb, const ggRenderOptions *ob);

/* Flush and close stdout; on failure print the reason and return EXIT_IO,
   else 0. */
int cli_close_stdout(void);

#endif
