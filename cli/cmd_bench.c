/* cmd_bench.c -- `ggrt bench`: not written yet (see the open issues). */
#include "cli.h"

int cmd_bench(int argc, char **argv)
{
    (void)argc;
    fprintf(stderr, "ggrt %s: not implemented yet\n", argv[0]);
    return EXIT_USAGE;
}
