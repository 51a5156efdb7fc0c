/* SPDX-License-Identifier: MIT */
/*
** cli.h -- the ggrt command line: subcommands and shared helpers.
** The CLI uses only the public API (<ggrt.h>).
*/
#ifndef GG_CLI_H
#define GG_CLI_H

#include "ggrt.h"

#include <stdio.h>

/* Exit codes (documented in ggrt(1)). */
#define EXIT_OK    0
#define EXIT_USAGE 1
#define EXIT_INPUT 2
#define EXIT_IO    3

/* Each subcommand: argv[0] is the subcommand's name. */
int cmd_optics(int argc, char **argv);
int cmd_render(int argc, char **argv);
int cmd_trace(int argc, char **argv);
int cmd_info(int argc, char **argv);
int cmd_bench(int argc, char **argv);
int cmd_serve(int argc, char **argv);

/* Map a library status to an exit code (INPUT for bad data, IO for files). */
int cli_exit_code(int status);
/* Parse "x,y,z"; returns 0 on success. */
int cli_parse_vec3(const char *s, ggVec3 *v);
/* Parse a finite double / an int in [lo, hi]; returns 0 on success. */
int cli_parse_double(const char *s, double *d);
int cli_parse_int(const char *s, long lo, long hi, int *out);
/* True if argument a is "-h" or "--help". */
int cli_is_help(const char *a);

#endif
