/* SPDX-License-Identifier: MIT */
/*
** child.c -- what every benchmark shares: medians, and one measurement in
** a child process so that its peak memory (ru_maxrss) is its own.
*/
/* wait4 (per-child peak memory) is a BSD interface. */
#define _DEFAULT_SOURCE
#include "bench/bench.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

double bench_median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

int bench_in_child(bench_fn fn, void *arg, void *out, size_t outsize, double *peak_mb)
{
    int fd[2], status;
    pid_t pid;
    struct rusage ru;
    ssize_t got = 0;
    if (pipe(fd) != 0) return -1;
    fflush(stdout);
    fflush(stderr);
    pid = fork();
    if (pid < 0) return -1;
    if (pid == 0) {
        int rc;
        close(fd[0]);
        memset(out, 0, outsize);
        rc = fn(arg, out);
        if (write(fd[1], out, outsize) != (ssize_t)outsize) rc = 1;
        _exit(rc ? 1 : 0);
    }
    close(fd[1]);
    while ((size_t)got < outsize) {
        ssize_t n = read(fd[0], (char *)out + got, outsize - (size_t)got);
        if (n <= 0) break;
        got += n;
    }
    close(fd[0]);
    if (wait4(pid, &status, 0, &ru) < 0) return -1;
    if (peak_mb) *peak_mb = ru.ru_maxrss / 1024.0;
    return (size_t)got == outsize && WIFEXITED(status) && WEXITSTATUS(status) == 0 ? 0 : -1;
}

const char *const bench_spd_scenes[] = {"balls-s4", "gears", "rings",     "tetra",
                                        "mount",    "tree",  "teapot-s12"};
typedef char
    bench_nspd_ok[sizeof bench_spd_scenes / sizeof *bench_spd_scenes == BENCH_NSPD ? 1 : -1];

int bench_unknown(const char *list, const char *const *names, int n, char *bad, size_t badsize)
{
    const char *p = list;
    for (;;) {
        size_t len = strcspn(p, ",");
        int i, found = 0;
        for (i = 0; i < n && !found; i++)
            found = strlen(names[i]) == len && !strncmp(p, names[i], len);
        if (!found) {
            snprintf(bad, badsize, "%.*s", (int)len, p);
            return 1;
        }
        if (!p[len]) return 0;
        p += len + 1;
    }
}

/* Whether the space-separated list `flags` holds the word f. */
static int has_flag(const char *flags, const char *f)
{
    size_t n = strlen(f);
    const char *p;
    for (p = flags; (p = strstr(p, f)); p += n)
        if ((p == flags || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return 1;
    return 0;
}

/* The CPU's model name from /proc/cpuinfo ("" where there is none) and
   which of AVX2 and AVX-512F its flags list. */
static void cpu_model(char *name, size_t n, int *avx2, int *avx512)
{
    char line[4096];
    FILE *f = fopen("/proc/cpuinfo", "r");
    int got_name = 0, got_flags = 0;
    name[0] = '\0', *avx2 = *avx512 = 0;
    if (!f) return;
    while ((!got_name || !got_flags) && fgets(line, sizeof line, f)) {
        char *v = strchr(line, ':');
        if (!v) continue;
        v += 1 + (v[1] == ' ');
        v[strcspn(v, "\n")] = '\0';
        if (!got_name && !strncmp(line, "model name", 10)) {
            snprintf(name, n, "%s", v);
            got_name = 1;
        } else if (!got_flags && !strncmp(line, "flags", 5)) {
            *avx2 = has_flag(v, "avx2");
            *avx512 = has_flag(v, "avx512f");
            got_flags = 1;
        }
    }
    fclose(f);
}

void bench_print_machine(void)
{
    static const char sphere[] = "f 1 1 1 1 0 0 0 0\ns 0 0 0 1\n";
    char name[256];
    int avx2, avx512;
    ggScene *s = ggSceneCreate(NULL);
    ggError err;
    const char *trav = NULL;
    cpu_model(name, sizeof name, &avx2, &avx512);
    if (s && ggSceneLoadString(s, sphere, sizeof sphere - 1, "probe.nff", &err) == GG_OK &&
        ggScenePrepare(s, &err) == GG_OK)
        trav = ggSceneTraversal(s);
    printf("cpu: %s (%s)\n", name[0] ? name : "unknown",
           avx512 ? "AVX-512F and AVX2"
           : avx2 ? "AVX2, no AVX-512F"
                  : "no AVX2");
    printf("ggrt: traversal %s%s\n", trav ? trav : "unknown",
           getenv("GGRT_ISA") ? " (GGRT_ISA is set)" : "");
    ggSceneFree(s);
}

const char *bench_row_name(const char *path)
{
    const char *b = strrchr(path, '/');
    return b ? b + 1 : path;
}

int bench_name_width(const bench_opts *bo)
{
    int i, w = 11;
    for (i = 0; i < bo->nargs; i++) {
        size_t n = strlen(bench_row_name(bo->args[i]));
        if (n > (size_t)w) w = n > 64 ? 64 : (int)n;
    }
    return w;
}

int bench_selected(const char *list, const char *name)
{
    const char *p;
    size_t n = strlen(name);
    if (!list) return 1;
    for (p = list; (p = strstr(p, name)); p += n)
        if ((p == list || p[-1] == ',') && (p[n] == '\0' || p[n] == ',')) return 1;
    return 0;
}
