/* cmd_info.c -- `ggrt info`: not written yet (see the open issues). */
#include "cli.h"

int cmd_info(int argc, char **argv)
{
    (void)argc;
    fprintf(stderr, "ggrt %s: not implemented yet\n", argv[0]);
    return EXIT_USAGE;
}
