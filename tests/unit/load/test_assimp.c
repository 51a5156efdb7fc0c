/* SPDX-License-Identifier: MIT */
/*
** test_assimp.c -- real files nobody here wrote: every OBJ and PLY model
** of Debian's assimp-testmodels package (/usr/share/assimp/models, which
** scripts/deps.sh installs for make check; GG_ASSIMP_MODELS names another
** copy). Each file either
**   - loads: its vertex and face counts equal an independent count (OBJ:
**     v and f statements counted here; PLY: the header's element lines),
**     and a 32x24 render of it, framed, has no non-finite pixel; or
**   - is one of the skips below, each with its reason, and is rejected
**     with an error naming the file and the expected cause.
** A skipped file that loads, a file that fails, or a wrong count is a
** failure. Prints one line per file and the summary line.
*/
#include "testutil.h"

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

typedef struct skip {
    const char *file;   /* path under the models folder */
    const char *kind;   /* the class of reason, for the summary */
    const char *reason; /* why the documented subset does not cover it */
    const char *error;  /* a part of the message the reader must give */
} skip;

static const skip skips[] = {
    {"OBJ/box_UTF16BE.obj", "UTF-16", "UTF-16 text (OBJ is read as ASCII/UTF-8)",
     "UTF-16 text is not supported"},
    {"OBJ/number_formats.obj", "malformed by design", "malformed numbers ('3.1+e2')",
     "expected a coordinate, got '3.1+e2'"},
    {"OBJ/point_cloud.obj", "no faces", "points only", "no faces"},
    {"OBJ/testline.obj", "no faces", "lines only", "no faces"},
    {"OBJ/testpoints.obj", "no faces", "points only", "no faces"},
    {"PLY/points.ply", "no faces", "a point cloud", "no faces"},
    {"PLY/pond.0.ply", "no faces", "a point cloud, and 69 bytes shorter than its header says",
     "truncated or a bad count"},
    {"PLY/issue623.ply", "malformed by design",
     "a list property in the vertex element that the data does not have, no face element",
     "vertex 0: expected a number, got the end of the line"},
    {"invalid/empty.obj", "empty", "an empty file", "no faces"},
    {"invalid/empty.ply", "empty", "an empty file", "not a PLY file"},
    {"invalid/malformed.obj", "malformed by design", "face indices out of range",
     "vertex index 12 is out of range"},
    {"invalid/malformed2.obj", "malformed by design", "a face with no vertices",
     "a face needs 3 or more corners, got 0"},
};
#define NSKIPS (sizeof skips / sizeof skips[0])
static int skip_seen[NSKIPS];

static char root[1024];
static int nloaded, nskipped, nfailed;

static char *slurp(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    char *buf;
    long n;
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    n = ftell(f);
    fseek(f, 0, SEEK_SET);
    buf = malloc((size_t)n + 1);
    if (buf && fread(buf, 1, (size_t)n, f) != (size_t)n) free(buf), buf = NULL;
    fclose(f);
    if (buf) buf[n] = '\0', *len = (size_t)n;
    return buf;
}

/* OBJ: count the v and f statements (a line ending in a backslash goes on
   on the next), and the most triangles the faces can give. */
static void count_obj(const char *t, size_t n, size_t *nv, size_t *nf, size_t *maxtri)
{
    size_t i = 0;
    *nv = *nf = *maxtri = 0;
    while (i < n) {
        size_t j = i, words = 0;
        int first = 0, inword = 0;
        for (; j < n && t[j] != '\n'; j++) {
            if (t[j] == '\\' && (j + 1 < n && (t[j + 1] == '\n' || (t[j + 1] == '\r' && j + 2 < n &&
                                                                    t[j + 2] == '\n')))) {
                j += t[j + 1] == '\r' ? 2 : 1;
                inword = 0;
                continue;
            }
            if (t[j] == ' ' || t[j] == '\t' || t[j] == '\r') {
                inword = 0;
                continue;
            }
            if (t[j] == '#' && !inword && words > 0) break;
            if (!inword) {
                inword = 1;
                if (words++ == 0)
                    first = (t[j] == 'v' || t[j] == 'f') && j + 1 < n &&
                                    (t[j + 1] == ' ' || t[j + 1] == '\t')
                                ? t[j]
                                : -1;
            }
        }
        if (first == 'v') (*nv)++;
        if (first == 'f') (*nf)++, *maxtri += words >= 3 ? words - 3 : 0;
        while (j < n && t[j] != '\n') j++;
        i = j + 1;
    }
}

/* PLY: the counts of the header's vertex and face elements. */
static void count_ply(const char *t, size_t *nv, size_t *nf)
{
    const char *e = strstr(t, "end_header"), *p;
    *nv = *nf = 0;
    for (p = strstr(t, "element "); p && (!e || p < e); p = strstr(p + 1, "element ")) {
        unsigned long long c;
        if (sscanf(p, "element vertex %llu", &c) == 1) *nv = (size_t)c;
        if (sscanf(p, "element face %llu", &c) == 1) *nf = (size_t)c;
    }
}

static const skip *skipped(const char *rel)
{
    size_t i;
    for (i = 0; i < sizeof skips / sizeof skips[0]; i++)
        if (!strcmp(skips[i].file, rel)) return &skips[i];
    return NULL;
}

/* Load, count, render. Returns 1 when all holds, printing why not. */
static int check_loaded(const char *path, const char *rel, ggScene *s)
{
    ggMeshInfo mi;
    ggRenderOptions o;
    ggImage *img = NULL;
    ggError e;
    size_t len, nv, nf, maxtri = 0;
    char *text = slurp(path, &len);
    int obj = strstr(rel, ".obj") != NULL, x, y, bad = 0;
    if (!text) return printf("FAIL    %s: cannot read it\n", rel), 0;
    if (obj)
        count_obj(text, len, &nv, &nf, &maxtri);
    else
        count_ply(text, &nv, &nf);
    free(text);
    ggSceneGetMeshInfo(s, 0, &mi);
    if (mi.file_vertices != nv || mi.file_faces != nf || !mi.triangles ||
        (obj && mi.triangles > maxtri))
        return printf("FAIL    %s: %zu vertices, %zu faces, %zu triangles read; counted %zu, %zu "
                      "(at most %zu triangles)\n",
                      rel, mi.file_vertices, mi.file_faces, mi.triangles, nv, nf, maxtri),
               0;
    ggRenderOptionsDefault(&o);
    o.width = 32, o.height = 24, o.threads = 1;
    if (ggRender(s, &o, &img, NULL, &e) != GG_OK)
        return printf("FAIL    %s: render: %s\n", rel, e.message), 0;
    for (y = 0; y < 24; y++)
        for (x = 0; x < 32; x++) {
            ggColor c = ggImageGet(img, x, y);
            bad += !isfinite(c.r) || !isfinite(c.g) || !isfinite(c.b);
        }
    ggImageFree(img);
    if (bad) return printf("FAIL    %s: %d non-finite pixels\n", rel, bad), 0;
    printf("loaded  %-36s %6zu vertices %6zu faces %6zu triangles, 32x24 finite%s%s\n", rel, nv, nf,
           mi.triangles, mi.warnings ? "; warning: " : "", mi.warnings ? mi.warning : "");
    return 1;
}

static void one(const char *path, const char *rel)
{
    const skip *sk = skipped(rel);
    ggScene *s = ggSceneCreate(NULL);
    ggError e;
    int rc = ggSceneLoadFile(s, path, &e);
    if (sk) {
        if (rc != GG_OK && strncmp(e.message, path, strlen(path)) == 0 &&
            strstr(e.message, sk->error)) {
            const char *why = e.message + strlen(path) + 1;
            while (*why == ' ') why++;
            printf("skipped %-36s %s: %s (rejected: %s)\n", rel, sk->kind, sk->reason, why);
            skip_seen[sk - skips] = 1;
            nskipped++;
        } else {
            printf("FAIL    %s: expected an error containing '%s', got %s\n", rel, sk->error,
                   rc == GG_OK ? "success" : e.message);
            nfailed++;
        }
    } else if (rc != GG_OK) {
        printf("FAIL    %s: %s\n", rel, e.message);
        nfailed++;
    } else if (check_loaded(path, rel, s)) {
        nloaded++;
    } else {
        nfailed++;
    }
    ggSceneFree(s);
}

static int by_name(const void *a, const void *b)
{
    return strcmp(*(const char *const *)a, *(const char *const *)b);
}

/* Every .obj and .ply under dir (sorted, so the output is stable). */
static void walk(const char *dir, const char *rel)
{
    DIR *d = opendir(dir);
    struct dirent *de;
    char *names[4096];
    size_t n = 0, i;
    if (!d) return;
    while ((de = readdir(d)) && n < 4096)
        if (de->d_name[0] != '.') names[n++] = strdup(de->d_name);
    closedir(d);
    qsort(names, n, sizeof *names, by_name);
    for (i = 0; i < n; i++) {
        char path[2048], r[1024];
        size_t l = strlen(names[i]);
        snprintf(path, sizeof path, "%s/%s", dir, names[i]);
        snprintf(r, sizeof r, "%s%s%s", rel, rel[0] ? "/" : "", names[i]);
        if (l > 4 &&
            (!strcasecmp(names[i] + l - 4, ".obj") || !strcasecmp(names[i] + l - 4, ".ply")))
            one(path, r);
        else if (!strchr(names[i], '.'))
            walk(path, r);
        free(names[i]);
    }
}

/* "N loaded, M skipped (k1 n1, k2 n2, ...), F failed": the skips by kind,
   counted from those actually seen. */
static void summary(void)
{
    size_t i, j;
    printf("assimp-testmodels: %d loaded, %d skipped (", nloaded, nskipped);
    for (i = 0; i < NSKIPS; i++) {
        int n = 0, first = 1;
        for (j = 0; j < i; j++)
            if (!strcmp(skips[j].kind, skips[i].kind)) first = 0;
        if (!first) continue;
        for (j = i; j < NSKIPS; j++) n += skip_seen[j] && !strcmp(skips[j].kind, skips[i].kind);
        printf("%s%s %d", i ? ", " : "", skips[i].kind, n);
    }
    printf("), %d failed\n", nfailed);
}

static void test_models(void **state)
{
    const char *env = getenv("GG_ASSIMP_MODELS");
    DIR *d;
    (void)state;
    snprintf(root, sizeof root, "%s", env && env[0] ? env : "/usr/share/assimp/models");
    if (!(d = opendir(root))) {
        printf(
            "assimp-testmodels: %s not found: apt-get install assimp-testmodels (scripts/deps.sh "
            "does for make check)\n",
            root);
        fail();
    }
    closedir(d);
    walk(root, "");
    summary();
    assert_int_equal(nfailed, 0);
    assert_int_equal(nskipped, (int)NSKIPS);
    assert_true(nloaded > 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_models)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
