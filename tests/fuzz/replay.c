/* SPDX-License-Identifier: MIT */
/*
** replay.c -- run a libFuzzer harness over corpus files without libFuzzer,
** so `make check` exercises the corpus with the plain compiler.
**   replay_NAME DIR_OR_FILE...
** Prints TAP (tests/run-tests.sh reads it): "ok N - FILE" after each input
** returns (a harness aborts on a broken property, so the input after the
** last "ok" is the one that broke it), then the plan "1..N".
*/
#include <dirent.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static int count;

/* Runs one input; -1 (and a "not ok" line) if it cannot be read. */
static int run_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    uint8_t *buf;
    long n;
    if (!f) {
        printf("not ok %d - %s: cannot open\n", ++count, path);
        return -1;
    }
    fseek(f, 0, SEEK_END);
    n = ftell(f);
    fseek(f, 0, SEEK_SET);
    buf = malloc(n > 0 ? (size_t)n : 1);
    if (!buf || (n > 0 && fread(buf, 1, (size_t)n, f) != (size_t)n)) {
        printf("not ok %d - %s: cannot read\n", ++count, path);
        fclose(f);
        free(buf);
        return -1;
    }
    fclose(f);
    LLVMFuzzerTestOneInput(buf, (size_t)n);
    free(buf);
    printf("ok %d - %s\n", ++count, path);
    fflush(stdout);
    return 0;
}

int main(int argc, char **argv)
{
    int i, rc = 0;
    for (i = 1; i < argc; i++) {
        struct stat st;
        if (stat(argv[i], &st) != 0) {
            printf("not ok %d - %s: no such corpus\n", ++count, argv[i]);
            rc = 1;
            continue;
        }
        if (S_ISDIR(st.st_mode)) {
            DIR *d = opendir(argv[i]);
            struct dirent *e;
            while (d && (e = readdir(d))) {
                char path[4096];
                if (e->d_name[0] == '.') continue;
                snprintf(path, sizeof path, "%s/%s", argv[i], e->d_name);
                if (run_file(path) != 0) rc = 1;
            }
            if (d) closedir(d);
        } else {
            if (run_file(argv[i]) != 0) rc = 1;
        }
    }
    if (count == 0) {
        printf("not ok 1 - no input in %s\n", argc > 1 ? argv[1] : "(no corpus named)");
        count = rc = 1;
    }
    printf("1..%d\n", count);
    if (rc == 0)
        printf("# replay %s: %d inputs, all properties held\n", argc > 1 ? argv[1] : "", count);
    return rc;
}
