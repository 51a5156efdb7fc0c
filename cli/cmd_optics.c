/* cmd_optics.c -- `ggrt optics`: not written yet (see the open issues). */
#include "cli.h"

int cmd_optics(int argc, char **argv)
{
    (void)argc;
    fprintf(stderr, "ggrt %s: not implemented yet\n", argv[0]);
    return EXIT_USAGE;
}
