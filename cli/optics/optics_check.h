/* SPDX-License-Identifier: MIT */
/*
** optics_check.h -- `ggrt optics check` and `ggrt optics seeds`
** (optics_check.c), which cmd_optics.c dispatches to; argv[0] is the
** word "check" or "seeds".
*/
#ifndef GG_CLI_OPTICS_CHECK_H
#define GG_CLI_OPTICS_CHECK_H

int cli_optics_check(int argc, char **argv);
int cli_optics_seeds(int argc, char **argv);

#endif
