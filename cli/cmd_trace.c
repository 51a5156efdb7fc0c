/* cmd_trace.c -- `ggrt trace`: not written yet (see the open issues). */
#include "cli.h"

int cmd_trace(int argc, char **argv)
{
    (void)argc;
    fprintf(stderr, "ggrt %s: not implemented yet\n", argv[0]);
    return EXIT_USAGE;
}
