/* SPDX-License-Identifier: MIT */
/*
** test_mesh_files.c -- the OBJ, MTL and PLY readers on the files in
** tests/data/meshes (what they read, names, lines, materials), the three
** PLY encodings agreeing, errors with their exact places, limits that
** fail before allocating, the NFF mesh keyword, and a model loaded as a
** scene of its own.
*/
#include "testutil.h"

#include "scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define DATA "tests/data/meshes/"

/* Loading `text` as `name` must fail with exactly this code and message,
   and leave the scene empty. */
static void expect_error(const char *text, size_t len, const char *name, int code, const char *msg)
{
    ggScene *s = ggSceneCreate(NULL);
    ggError e;
    int rc = ggSceneLoadMeshMemory(s, text, len, name, NULL, &e);
    if (rc != code || strcmp(e.message, msg))
        print_error("got %d '%s'\nwant %d '%s'\n", rc, rc ? e.message : "", code, msg);
    assert_int_equal(rc, code);
    assert_string_equal(e.message, msg);
    assert_int_equal(ggSceneObjectCount(s), 0);
    assert_int_equal(ggSceneMaterialCount(s), 0);
    assert_int_equal(ggSceneMeshCount(s), 0);
    ggSceneFree(s);
}

/* Each ascii PLY body after header h fails with its message. */
typedef struct ply_bad {
    const char *body, *msg;
} ply_bad;

static void expect_bodies(const char *h, const ply_bad *bad, size_t n)
{
    char text[400];
    size_t i;
    for (i = 0; i < n; i++) {
        snprintf(text, sizeof text, "%s%s", h, bad[i].body);
        expect_error(text, strlen(text), "t.ply", GG_ERROR_PARSE, bad[i].msg);
    }
}

#define EXPECT(text, code, msg) expect_error(text, strlen(text), "t.obj", code, msg)

static void test_obj_cube(void **state)
{
    ggScene *s = ggSceneCreate(NULL);
    ggMeshInfo mi;
    ggFaceInfo fi;
    ggMaterial red, glass;
    ggError e;
    int i, lines[6] = {22, 25, 29, 30, 33, 36}, seen = 0;
    (void)state;
    assert_int_equal(ggSceneLoadMesh(s, DATA "cube.obj", NULL, &e), GG_OK);
    assert_int_equal(ggSceneGetMeshInfo(s, 0, &mi), GG_OK);
    assert_string_equal(mi.format, "obj");
    assert_int_equal(mi.file_vertices, 8);
    assert_int_equal(mi.file_faces, 6);
    assert_int_equal(mi.triangles, 12);
    assert_int_equal(mi.groups, 4);  /* cube, cube/bottom, cube/top, cube/sides */
    assert_int_equal(mi.ignored, 2); /* l, and Ka in the MTL file */
    assert_true(mi.has_uv);
    assert_int_equal(mi.objects, 3); /* red, glass, and the default material */
    assert_int_equal(mi.warnings, 1);
    assert_string_equal(mi.warning, DATA "cube.obj: usemtl 'nosuchmaterial' names no material "
                                         "of the MTL files; its faces get the default material");
    for (i = 0; i < 12; i++) {
        int obj = i < 8 ? 0 : i < 10 ? 1 : 2; /* red has 4 faces, glass 1, default 1 */
        assert_int_equal(ggSceneGetFaceInfo(s, obj, i, &fi), GG_OK);
        assert_int_equal(fi.line, lines[fi.face]);
        seen |= 1 << fi.face;
        if (fi.face == 1) {
            assert_string_equal(fi.group, "cube/top");
            assert_string_equal(fi.material_name, "glass");
        }
        if (fi.face == 4) assert_string_equal(fi.group, "cube/sides");
        if (fi.face == 5) assert_int_equal(fi.material, ggSceneObjectMaterial(s, 2));
    }
    assert_int_equal(seen, 63);
    /* the mapping of docs/scene-format.md */
    red = ggSceneMaterial(s, ggSceneObjectMaterial(s, 0));
    glass = ggSceneMaterial(s, ggSceneObjectMaterial(s, 1));
    assert_true(red.color.r == 0.8 && red.color.g == 0.1 && red.kd == 1);
    assert_true(red.ks == 0 && red.kt == 0 && red.texture == 0); /* illum 2: no mirror */
    assert_true(glass.kt == 1 - 0.1 && glass.kd == 1 - glass.kt && glass.ior == 1.5);
    assert_true(glass.ks == 0.1 && glass.shine == 200 && glass.fresnel == GG_FRESNEL_EXACT);
    /* texture coordinates: the top face's vt run with x and y; OBJ's v is
       flipped into ggrt's (v = 0 the image's top row) */
    {
        ggHit h;
        ggRay r = {{0.25, 0.75, 3}, {0, 0, -1}};
        assert_int_equal(ggScenePrepare(s, &e), GG_OK);
        assert_true(ggSceneIntersect(s, r, 0, INFINITY, &h));
        assert_close(h.u, 0.25, 1e-12);
        assert_close(h.v, 1 - 0.75, 1e-12);
    }
    ggSceneFree(s);
}

/* Reading from memory follows no mtllib; the same geometry. */
static void test_obj_memory(void **state)
{
    size_t len;
    char *text = tu_slurp(DATA "cube.obj", &len);
    ggScene *s = ggSceneCreate(NULL);
    ggMeshInfo mi;
    ggError e;
    (void)state;
    assert_int_equal(ggSceneLoadMeshMemory(s, text, len, "cube.obj", NULL, &e), GG_OK);
    ggSceneGetMeshInfo(s, 0, &mi);
    assert_int_equal(mi.triangles, 12);
    assert_int_equal(mi.ignored, 2); /* l, mtllib */
    assert_int_equal(s->ntextures, 0);
    free(text);
    ggSceneFree(s);
}

static void test_obj_errors(void **state)
{
    static char big[2200000];
    size_t k;
    (void)state;
    EXPECT("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", GG_ERROR_PARSE,
           "t.obj:4:7: vertex index 9 is out of range (3 defined so far)");
    EXPECT("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", GG_ERROR_PARSE,
           "t.obj:4:7: vertex index -4 is out of range (3 defined so far)");
    EXPECT("v 0 0 0\nf 0 1 1\n", GG_ERROR_PARSE,
           "t.obj:2:3: vertex index 0 (OBJ indices start at 1)");
    EXPECT("v 0 0 0\nf 1/1 1 1\n", GG_ERROR_PARSE,
           "t.obj:2:5: texture coordinate index 1 is out of range (0 defined so far)");
    EXPECT("v 1 2 nan\n", GG_ERROR_PARSE, "t.obj:1:7: expected a coordinate, got 'nan'");
    EXPECT("v 1 2 1e999\n", GG_ERROR_PARSE, "t.obj:1:7: expected a coordinate, got '1e999'");
    EXPECT("v 1 2\n", GG_ERROR_PARSE, "t.obj:1:6: expected a coordinate, got the end of the line");
    EXPECT("v 1 2 3 x\n", GG_ERROR_PARSE, "t.obj:1:9: expected a number, got 'x'");
    EXPECT("v 0 0 0\nf 1 1\n", GG_ERROR_PARSE, "t.obj:2:6: a face needs 3 or more corners, got 2");
    EXPECT("v 0 0 0\nf 1/1/1/1 1 1\n", GG_ERROR_PARSE,
           "t.obj:2:5: texture coordinate index 1 is out of range (0 defined so far)");
    EXPECT("v 0 0 0\nvn 0 0 1\nf 1//1/ 1 1\n", GG_ERROR_PARSE,
           "t.obj:3:7: unexpected '/' in a face corner");
    /* an index is a whole number: said of 0x1 and of one beyond the range */
    EXPECT("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0x1 2 3\n", GG_ERROR_PARSE,
           "t.obj:4:3: expected a vertex index, got '0x1'");
    EXPECT("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999\n", GG_ERROR_PARSE,
           "t.obj:4:7: vertex index 99999999999999999999 is out of range (3 defined so far)");
    EXPECT("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/x 2 3\n", GG_ERROR_PARSE,
           "t.obj:4:5: expected a texture coordinate index, got 'x'");
    EXPECT("v 0 0 0\ns maybe\n", GG_ERROR_PARSE,
           "t.obj:2:3: expected a smoothing group number or off");
    EXPECT("v 0 0 0\nv 0\xc0 0 0\n", GG_ERROR_PARSE,
           "t.obj:2:3: expected a coordinate, got '0\\xC0'");
    expect_error("v 0 0 0\nv 1\0 0 0\n", 16, "t.obj", GG_ERROR_PARSE,
                 "t.obj:2:4: NUL byte in a text file");
    expect_error("\xff\xfev\0 \0", 6, "t.obj", GG_ERROR_UNSUPPORTED,
                 "t.obj:1:1: UTF-16 text is not supported (convert the file to UTF-8)");
    EXPECT("v 0 0 0\nl 1 1\np 1\n", GG_ERROR_PARSE,
           "t.obj: no faces (1 vertices; 2 statements not read: points, lines, curves or unknown)");
    EXPECT("", GG_ERROR_PARSE,
           "t.obj: no faces (0 vertices; 0 statements not read: points, lines, curves or unknown)");
    /* a face of more than 2^20 corners fails on the count, not on memory */
    memcpy(big, "v 0 0 0\nf", 9);
    for (k = 9; k + 2 < sizeof big - 1; k += 2) big[k] = ' ', big[k + 1] = '1';
    big[k] = '\n', big[k + 1] = '\0';
    EXPECT(big, GG_ERROR_LIMIT, "t.obj:2:2097155: a face has more than 1048576 corners");
}

/* Line continuations, negative indices, polygons, and what counts. */
static void test_obj_forms(void **state)
{
    const char *text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0.5 0.2 0\nv 0 1 0\n"
                       "# a concave pentagon, written across two lines\n"
                       "f 1 2 \\\n 3 4 5\n"
                       "f -5 -4 -3\n"
                       "vp 0.5\ncurv 0 1 1 2\n";
    ggScene *s = ggSceneCreate(NULL);
    ggMeshInfo mi;
    ggFaceInfo fi;
    ggError e;
    (void)state;
    assert_int_equal(ggSceneLoadMeshMemory(s, text, strlen(text), "t.obj", NULL, &e), GG_OK);
    ggSceneGetMeshInfo(s, 0, &mi);
    assert_int_equal(mi.file_faces, 2);
    assert_int_equal(mi.triangles, 4); /* 3 for the pentagon, 1 */
    assert_int_equal(mi.ignored, 2);
    assert_int_equal(ggSceneGetFaceInfo(s, 0, 3, &fi), GG_OK);
    assert_int_equal(fi.face, 1);
    assert_int_equal(fi.line, 9);
    ggSceneFree(s);
    /* an empty field before the end of the line, a CR or a comment is
       none, as before a blank (`f 1/ 2/ 3/` was refused, with a space
       after it read) */
    {
        static const char *const faces[] = {"f 1/ 2/ 3/\n",      "f 1/ 2/ 3/ \n",   "f 1/ 2/ 3/",
                                            "f 1// 2// 3//\r\n", "f 1/ 2/ 3/# c\n", "f 1/ 2/ 3/\r"};
        char t[100];
        size_t i;
        for (i = 0; i < sizeof faces / sizeof faces[0]; i++) {
            s = ggSceneCreate(NULL);
            snprintf(t, sizeof t, "v 0 0 0\nv 1 0 0\nv 0 1 0\n%s", faces[i]);
            if (ggSceneLoadMeshMemory(s, t, strlen(t), "t.obj", NULL, &e) != GG_OK)
                print_error("'%s': %s\n", faces[i], e.message);
            assert_int_equal(ggSceneMeshCount(s), 1);
            ggSceneFree(s);
        }
    }
}

/* Group labels: one per distinct "o/g" however often a pair comes back,
   and an o alone, a g alone or o "a/b" give the labels they spell. */
static void test_obj_groups(void **state)
{
    const char *text = "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
                       "o a\ng b\nf 1 2 3\ng c\nf 1 2 3\ng b\nf 1 2 3\n"
                       "o a/b\nf 1 2 3\no\ng d\nf 1 2 3\no a\nf 1 2 3\n";
    const char *want[6] = {"a/b", "a/c", "a/b", "a/b", "d", "a"};
    ggScene *s = ggSceneCreate(NULL);
    ggMeshInfo mi;
    ggFaceInfo fi;
    ggError e;
    int i;
    (void)state;
    assert_int_equal(ggSceneLoadMeshMemory(s, text, strlen(text), "t.obj", NULL, &e), GG_OK);
    ggSceneGetMeshInfo(s, 0, &mi);
    assert_int_equal(mi.groups, 4); /* a, a/b, a/c, d */
    for (i = 0; i < 6; i++) {
        assert_int_equal(ggSceneGetFaceInfo(s, 0, i, &fi), GG_OK);
        assert_string_equal(fi.group, want[fi.face]);
    }
    ggSceneFree(s);
}

/* A '#' after a blank starts a comment in a name (o, g, usemtl, mtllib,
   newmtl): `mtllib red.mtl # c` warned it could not read '#', `usemtl
   red # c` named 'red # c' and gave the default material. A '#' inside
   a word is part of the name. */
static void test_obj_name_comments(void **state)
{
    const char *obj = "mtllib build_test_names.mtl # the library\n"
                      "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
                      "g a # first\nusemtl red # c\nf 1 2 3\n"
                      "g b#2\nusemtl a#1\nf 1 2 3\n";
    FILE *f = fopen("build_test_names.mtl", "w");
    ggScene *s = ggSceneCreate(NULL);
    ggMeshInfo mi;
    ggFaceInfo fi;
    ggError e;
    int i;
    (void)state;
    assert_non_null(f);
    fprintf(f, "newmtl red # c\nKd 1 0 0\nnewmtl a#1\nKd 0 0 1\n");
    fclose(f);
    f = fopen("build_test_names.obj", "w");
    assert_non_null(f);
    fputs(obj, f);
    fclose(f);
    if (ggSceneLoadMesh(s, "build_test_names.obj", NULL, &e) != GG_OK)
        print_error("%s\n", e.message);
    assert_int_equal(ggSceneGetMeshInfo(s, 0, &mi), GG_OK);
    if (mi.warnings) print_error("%s\n", mi.warning);
    assert_int_equal(mi.warnings, 0);
    for (i = 0; i < 2; i++) {
        assert_int_equal(ggSceneGetFaceInfo(s, 0, i, &fi), GG_OK);
        assert_string_equal(fi.group, fi.face ? "b#2" : "a");
        assert_string_equal(fi.material_name, fi.face ? "a#1" : "red");
        assert_true(ggSceneMaterial(s, fi.material).color.r == (fi.face ? 0 : 1));
    }
    remove("build_test_names.obj");
    remove("build_test_names.mtl");
    ggSceneFree(s);
}

/* Each distinct (o, g) pair stores its whole label: one 400,000-byte o
   name and 60 g names asked for 24 MB (500 of them 200 MB). Their bytes
   may pass the file's size by GG_MESH_LABELS_MAX, no more. */
static void test_obj_label_limit(void **state)
{
    size_t len = 0, k;
    char *text = malloc(500000), msg[300];
    (void)state;
    assert_non_null(text);
    memcpy(text, "o ", 2), len = 2;
    memset(text + len, 'a', 400000), len += 400000;
    len += (size_t)sprintf(text + len, "\nv 0 0 0\nv 1 0 0\nv 0 1 0\n");
    for (k = 0; k < 60; k++) len += (size_t)sprintf(text + len, "g g%zu\nf 1 2 3\n", k);
    /* (o, "") and 41 pairs (o, gK) fit: the 42nd, g41 at line 5 + 2 * 41 */
    snprintf(msg, sizeof msg,
             "t.obj:87:3: the group labels would pass %zu bytes, the file's size plus 16 MiB "
             "(each distinct o and g pair stores its \"o/g\" label)",
             len + GG_MESH_LABELS_MAX);
    expect_error(text, len, "t.obj", GG_ERROR_LIMIT, msg);
    free(text);
}

/* A load that fails after its materials and textures were added keeps
   none of them. */
static void test_obj_rollback(void **state)
{
    ggScene *s = ggSceneCreate(NULL);
    ggError e;
    (void)state;
    assert_int_equal(ggSceneLoadMesh(s, DATA "flat.obj", NULL, &e), GG_ERROR_PARSE);
    assert_string_equal(e.message, DATA "flat.obj: no face has an area");
    assert_int_equal(ggSceneMaterialCount(s), 0);
    assert_int_equal(s->ntextures, 0);
    assert_int_equal(ggSceneObjectCount(s), 0);
    ggSceneFree(s);
}

/* A concave quad is split along the diagonal inside it: the notch at
   (0.5, 1) stays empty. */
static void test_obj_concave_quad(void **state)
{
    const char *text = "v 0 0 0\nv 2 1 0\nv 0 2 0\nv 0.5 1 0\nf 1 2 3 4\n";
    ggScene *s = ggSceneCreate(NULL);
    ggError e;
    ggHit h;
    ggRay in = {{1, 1, 1}, {0, 0, -1}}, notch = {{0.2, 1, 1}, {0, 0, -1}};
    (void)state;
    assert_int_equal(ggSceneLoadMeshMemory(s, text, strlen(text), "t.obj", NULL, &e), GG_OK);
    assert_int_equal(ggScenePrepare(s, &e), GG_OK);
    assert_true(ggSceneIntersect(s, in, 0, INFINITY, &h));
    assert_false(ggSceneIntersect(s, notch, 0, INFINITY, &h));
    ggSceneFree(s);
}

/* The concave pentagon's triangles cover it exactly: their areas add up
   to its area, and none sticks out of the notch at (0.5, 0.2). */
static void test_obj_concave(void **state)
{
    const char *text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0.5 0.2 0\nv 0 1 0\nf 1 2 3 4 5\n";
    ggScene *s = ggSceneCreate(NULL);
    ggError e;
    ggHit h;
    ggRay in = {{0.1, 0.5, 1}, {0, 0, -1}}, notch = {{0.5, 0.5, 1}, {0, 0, -1}};
    (void)state;
    assert_int_equal(ggSceneLoadMeshMemory(s, text, strlen(text), "t.obj", NULL, &e), GG_OK);
    assert_int_equal(ggScenePrepare(s, &e), GG_OK);
    assert_true(ggSceneIntersect(s, in, 0, INFINITY, &h));
    assert_false(ggSceneIntersect(s, notch, 0, INFINITY, &h));
    ggSceneFree(s);
}

/* The same cube in ascii, little and big endian: the same mesh. */
static void test_ply_encodings(void **state)
{
    const char *names[3] = {DATA "cube_ascii.ply", DATA "cube_le.ply", DATA "cube_be.ply"};
    ggScene *s[3];
    int i;
    (void)state;
    for (i = 0; i < 3; i++) {
        ggMeshInfo mi;
        ggError e;
        s[i] = ggSceneCreate(NULL);
        if (ggSceneLoadMesh(s[i], names[i], NULL, &e) != GG_OK) print_error("%s\n", e.message);
        assert_int_equal(ggSceneGetMeshInfo(s[i], 0, &mi), GG_OK);
        assert_string_equal(mi.format, "ply");
        assert_int_equal(mi.file_vertices, 8);
        assert_int_equal(mi.file_faces, 6);
        assert_int_equal(mi.triangles, 12);
        assert_int_equal(mi.ignored, 1); /* the edge element */
    }
    for (i = 1; i < 3; i++) {
        const gg_mesh *a = &s[0]->meshes[0], *b = &s[i]->meshes[0];
        assert_int_equal(a->nverts, b->nverts);
        assert_memory_equal(a->pos, b->pos, a->nverts * sizeof *a->pos);
        assert_memory_equal(a->nrm, b->nrm, a->nverts * sizeof *a->nrm);
        assert_memory_equal(a->idx, b->idx, 3 * a->ntri * sizeof *a->idx);
    }
    for (i = 0; i < 3; i++) ggSceneFree(s[i]);
}

/* After a binary body: a closing newline is a writer's habit and loads;
   any other byte means the header's counts are short of the data, which
   loaded without a word until an audit. */
static void test_ply_binary_rest(void **state)
{
    size_t len, i;
    char *body = tu_slurp(DATA "cube_le.ply", &len), *buf;
    (void)state;
    assert_non_null(body);
    buf = malloc(len + 2);
    assert_non_null(buf);
    memcpy(buf, body, len);
    for (i = 0; i < 2; i++) {
        ggScene *s = ggSceneCreate(NULL);
        ggError e;
        char want[128];
        int rc;
        buf[len] = i ? '\x01' : '\n', buf[len + 1] = i ? '\x02' : '\r';
        rc = ggSceneLoadMeshMemory(s, buf, len + 2, "t.ply", NULL, &e);
        if (i == 0) {
            assert_int_equal(rc, GG_OK);
        } else {
            snprintf(want, sizeof want,
                     "t.ply: byte %zu: 2 bytes after the elements the header declares", len);
            assert_int_equal(rc, GG_ERROR_PARSE);
            assert_string_equal(e.message, want);
            assert_int_equal(ggSceneObjectCount(s), 0);
        }
        ggSceneFree(s);
    }
    free(buf);
    free(body);
}

/* Byte offsets, element indices and limits in binary PLY. */
static void test_ply_errors(void **state)
{
    size_t len, hdr;
    char *le = tu_slurp(DATA "cube_le.ply", &len), *t = malloc(len + 64), msg[200];
    float nan = NAN;
    int32_t big = 99;
    (void)state;
    hdr = (size_t)(strstr(le, "end_header\n") - le) + 11;
    /* vertices are 15 bytes, faces 18 (count, 4 ints, flags) */
    memcpy(t, le, len);
    memcpy(t + hdr + 3 * 15 + 4, &nan, 4);
    snprintf(msg, sizeof msg,
             "t.ply: byte %zu (vertex 3): a coordinate, normal or texture "
             "coordinate is not finite",
             hdr + 3 * 15 /* where vertex 3 starts */);
    expect_error(t, len, "t.ply", GG_ERROR_PARSE, msg);
    memcpy(t, le, len);
    memcpy(t + hdr + 8 * 15 + 2 * 18 + 1 + 8, &big, 4);
    snprintf(msg, sizeof msg,
             "t.ply: byte %zu (face 2): vertex index 99 is out of range (8 vertices)",
             hdr + 8 * 15 + 2 * 18 + 1 + 8 /* the index */);
    expect_error(t, len, "t.ply", GG_ERROR_PARSE, msg);
    /* cut inside face 4 */
    snprintf(msg, sizeof msg,
             "t.ply: byte %zu (face 4): the file ends inside this list of 4 indices (truncated)",
             hdr + 8 * 15 + 4 * 18 + 1);
    expect_error(le, hdr + 8 * 15 + 4 * 18 + 10, "t.ply", GG_ERROR_PARSE, msg);
    /* cut inside the vertices: said before reading them */
    snprintf(msg, sizeof msg,
             "t.ply: byte %zu (vertex 0): 8 vertex elements need at least 120 "
             "bytes, 100 are left (truncated or a bad count)",
             hdr);
    expect_error(le, hdr + 100, "t.ply", GG_ERROR_PARSE, msg);
    free(le);
    free(t);
    /* counts beyond the limit, or beyond what the file holds */
    {
        const char *h = "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n"
                        "property float x\nproperty float y\nproperty float z\nend_header\n";
        const char *h2 = "ply\nformat binary_little_endian 1.0\nelement vertex 200000000\n"
                         "property float x\nproperty float y\nproperty float z\nend_header\n";
        expect_error(h, strlen(h), "t.ply", GG_ERROR_LIMIT,
                     "t.ply: byte 124 (vertex 0): more than 2^28 vertices");
        expect_error(h2, strlen(h2), "t.ply", GG_ERROR_PARSE,
                     "t.ply: byte 123 (vertex 0): 200000000 vertex elements need at least "
                     "2400000000 bytes, 0 are left (truncated or a bad count)");
    }
    /* a count error names the element's index 0, not the count of the
       element before; in ascii it is at the count in the header */
    {
        const char *bh = "ply\nformat binary_little_endian 1.0\nelement vertex 2\n"
                         "property float x\nproperty float y\nproperty float z\n"
                         "element face 1000\nproperty list uchar int vertex_indices\nend_header\n";
        const char *ah = "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\n"
                         "property float y\nproperty float z\nelement face 100\n"
                         "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n";
        char b[400];
        size_t hl = strlen(bh);
        memset(b, 0, sizeof b);
        memcpy(b, bh, hl);
        snprintf(msg, sizeof msg,
                 "t.ply: byte %zu (face 0): 1000 face elements need at least 1000 bytes, 0 "
                 "are left (truncated or a bad count)",
                 hl + 24);
        expect_error(b, hl + 24, "t.ply", GG_ERROR_PARSE, msg);
        expect_error(ah, strlen(ah), "t.ply", GG_ERROR_PARSE,
                     "t.ply:7:14: 100 face elements need at least 200 bytes, 0 are left "
                     "(truncated or a bad count)");
    }
    {
        const char *a =
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
            "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
            "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n";
        const char *b =
            "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
            "property float z\nend_header\n0 0 inf\n";
        const char *c =
            "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\n"
            "element vertex 1\nproperty float x\nend_header\n3 0 0 0\n0\n";
        expect_error(a, strlen(a), "t.ply", GG_ERROR_PARSE,
                     "t.ply:13:7: face 0: vertex index 3 is out of range (3 vertices)");
        expect_error(b, strlen(b), "t.ply", GG_ERROR_PARSE,
                     "t.ply:8:5: vertex 0: expected a number");
        expect_error(c, strlen(c), "t.ply", GG_ERROR_UNSUPPORTED,
                     "t.ply:8:1: face 0: faces before the vertex element are not supported");
        expect_error("ply\nformat ascii 1.0\n", 20, "t.ply", GG_ERROR_PARSE,
                     "t.ply:3:1: the header has no end_header line");
        expect_error("PLY\n", 4, "t.ply", GG_ERROR_PARSE, "t.ply: not a PLY file (no 'ply' line)");
    }
}

/* Index n (a face corner) written as a PLY value of `size` bytes in
   either byte order. */
static size_t put_index(unsigned char *b, unsigned n, int size, int big)
{
    int i;
    for (i = 0; i < size; i++) b[big ? size - 1 - i : i] = (unsigned char)(n >> (8 * i));
    return (size_t)size;
}

/* A binary face with corner 3 of 3 vertices, one past the last, is
   refused with the byte of that index, for every index type and both byte
   orders; corners 0, 1, 2 load. Native-endian int and uint indices take a
   fast path of their own (face_indices in lib/load/ply.c compares the raw
   uint32 with the vertex count): this guards its `u >= nv` (`u > nv`
   accepted index 3 and read past the vertices), the others the general
   path's `d < nv`. */
static void test_ply_binary_index_bound(void **state)
{
    static const struct {
        const char *name;
        int size;
    } types[] = {{"int", 4},  {"uint", 4},   {"int32", 4}, {"uint32", 4}, {"uchar", 1},
                 {"char", 1}, {"ushort", 2}, {"short", 2}, {"uint16", 2}};
    size_t t;
    int big, last;
    (void)state;
    for (big = 0; big < 2; big++)
        for (t = 0; t < sizeof types / sizeof types[0]; t++)
            for (last = 2; last <= 3; last++) {
                unsigned char b[400];
                char msg[160];
                static const float xyz[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
                size_t n, hl, at;
                int i, j;
                n = (size_t)snprintf((char *)b, sizeof b,
                                     "ply\nformat binary_%s_endian 1.0\nelement vertex 3\n"
                                     "property float x\nproperty float y\nproperty float z\n"
                                     "element face 1\nproperty list uchar %s vertex_indices\n"
                                     "end_header\n",
                                     big ? "big" : "little", types[t].name);
                hl = n;
                for (i = 0; i < 9; i++) {
                    uint32_t u;
                    memcpy(&u, &xyz[i], 4);
                    for (j = 0; j < 4; j++)
                        b[n + (size_t)(big ? 3 - j : j)] = (unsigned char)(u >> (8 * j));
                    n += 4;
                }
                b[n++] = 3;
                n += put_index(b + n, 0, types[t].size, big);
                n += put_index(b + n, 1, types[t].size, big);
                at = n;
                n += put_index(b + n, (unsigned)last, types[t].size, big);
                if (last == 2) {
                    ggScene *s = ggSceneCreate(NULL);
                    ggError e;
                    int rc = ggSceneLoadMeshMemory(s, (const char *)b, n, "t.ply", NULL, &e);
                    if (rc != GG_OK) print_error("%s: %s\n", types[t].name, e.message);
                    assert_int_equal(rc, GG_OK);
                    ggSceneFree(s);
                } else {
                    snprintf(msg, sizeof msg,
                             "t.ply: byte %zu (face 0): vertex index 3 is out of range "
                             "(3 vertices)",
                             at);
                    expect_error((const char *)b, n, "t.ply", GG_ERROR_PARSE, msg);
                }
                assert_true(at == hl + 36 + 1 + 2 * (size_t)types[t].size);
            }
}

/* An ascii PLY element is one line holding its values, no more, no
   fewer, and the body has the lines the header declares: values once ran
   on across lines, and lines beyond the counts were dropped. Lines may
   end in LF, CRLF or a lone CR. */
static void test_ply_ascii_lines(void **state)
{
    const char *h = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                    "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                    "end_header\n";
    static const ply_bad bad[] = {
        {"0 0\n1 0 0 0\n1 0\n3 0 1 2\n",
         "t.ply:10:4: vertex 0: expected a number, got the end of the line"},
        {"0 0 0\n1 0 0\n0 1 0\n3 0 1 2 junk\n",
         "t.ply:13:9: face 0: expected the end of the line, got 'junk'"},
        {"0 0 0\n1 0 0\n0 1 0\n3 0 1\n2\n",
         "t.ply:13:6: face 0: expected a number, got the end of the line"},
        {"0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 2 1 0\n",
         "t.ply:14:1: '3': more lines than the header's element counts declare"},
        {"0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n\n  \n0 0 0\n",
         "t.ply:16:1: '0': more lines than the header's element counts declare"},
    };
    const char *lf = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                     "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                     "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n\n";
    char cr[400];
    size_t i;
    (void)state;
    expect_bodies(h, bad, sizeof bad / sizeof bad[0]);
    /* the same file with LF and with lone CR line endings: one mesh */
    for (i = 0; lf[i]; i++) cr[i] = lf[i] == '\n' ? '\r' : lf[i];
    cr[i] = '\0';
    {
        ggScene *s[2];
        ggError e;
        int k;
        for (k = 0; k < 2; k++) {
            const char *t = k ? cr : lf;
            s[k] = ggSceneCreate(NULL);
            if (ggSceneLoadMeshMemory(s[k], t, strlen(t), "t.ply", NULL, &e) != GG_OK)
                print_error("%s\n", e.message);
            assert_int_equal(ggSceneMeshCount(s[k]), 1);
        }
        assert_int_equal(s[0]->meshes[0].nverts, s[1]->meshes[0].nverts);
        assert_int_equal(s[0]->meshes[0].ntri, 1);
        assert_memory_equal(s[0]->meshes[0].pos, s[1]->meshes[0].pos,
                            s[0]->meshes[0].nverts * sizeof *s[0]->meshes[0].pos);
        for (k = 0; k < 2; k++) ggSceneFree(s[k]);
    }
}

/* An ascii value fits its declared type (`property uchar x` took 300 and
   -5), and the header says its format and version (without them a file
   loaded as ascii). */
static void test_ply_values(void **state)
{
    const char *h = "ply\nformat ascii 1.0\nelement vertex 3\nproperty uchar x\nproperty float y\n"
                    "property short z\nelement face 1\nproperty list uchar int vertex_indices\n"
                    "end_header\n";
    static const ply_bad bad[] = {
        {"300 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
         "t.ply:10:1: vertex 0: a uchar must be a whole number from 0 to 255, got 300"},
        {"0 0 0\n-5 0 0\n0 1 0\n3 0 1 2\n",
         "t.ply:11:1: vertex 1: a uchar must be a whole number from 0 to 255, got -5"},
        {"0 0 0\n1 0 0\n0 1 0.5\n3 0 1 2\n",
         "t.ply:12:5: vertex 2: a short must be a whole number from -32768 to 32767, got 0.5"},
        {"0 1e39 0\n1 0 0\n0 1 0\n3 0 1 2\n",
         "t.ply:10:3: vertex 0: 1e39 is beyond the range of a float (+-3.40282347e+38)"},
        {"0 0 0\n1 0 0\n0 1 0\n256 0 1 2\n",
         "t.ply:13:1: face 0: a uchar must be a whole number from 0 to 255, got 256"},
        {"0 0 0\n1 0 0\n0 1 0\n3 0 1 2147483648\n",
         "t.ply:13:7: face 0: an int must be a whole number from -2147483648 to 2147483647, got "
         "2147483648"},
    };
    static const struct {
        const char *text, *msg;
    } hdr[] = {
        {"ply\nelement vertex 0\nend_header\n",
         "t.ply:3:1: the header has no format line (format ascii 1.0, binary_little_endian 1.0 "
         "or binary_big_endian 1.0)"},
        {"ply\nformat ascii\nelement vertex 0\nend_header\n",
         "t.ply:2:13: the format needs its version (1.0)"},
        {"ply\nformat ascii 2.0\nelement vertex 0\nend_header\n",
         "t.ply:2:14: unsupported format version '2.0' (PLY defines 1.0)"},
        {"ply\nformat binary_little_endian 1.0 x\nend_header\n", "t.ply:2:33: unexpected 'x'"},
        {"ply\nformat ascii 1.0\nformat binary_little_endian 1.0\nend_header\n",
         "t.ply:3:1: a second format line"},
        {"ply\nelement vertex 0\nformat ascii 1.0\nend_header\n",
         "t.ply:3:1: the format line must come before the elements"},
    };
    size_t i;
    (void)state;
    expect_bodies(h, bad, sizeof bad / sizeof bad[0]);
    for (i = 0; i < sizeof hdr / sizeof hdr[0]; i++)
        expect_error(hdr[i].text, strlen(hdr[i].text), "t.ply", GG_ERROR_PARSE, hdr[i].msg);
    /* the limits themselves load; `format ascii 1` is version 1.0 too */
    {
        const char *ok = "ply\nformat ascii 1\nelement vertex 3\nproperty uchar x\n"
                         "property char y\nproperty int z\nelement face 1\n"
                         "property list uchar uint vertex_indices\nend_header\n"
                         "255 -128 -2147483648\n0 127 2147483647\n0 0 0\n3 0 1 2\n";
        ggScene *s = ggSceneCreate(NULL);
        ggError e;
        if (ggSceneLoadMeshMemory(s, ok, strlen(ok), "t.ply", NULL, &e) != GG_OK)
            print_error("%s\n", e.message);
        assert_int_equal(ggSceneMeshCount(s), 1);
        ggSceneFree(s);
    }
}

/* NFF: mesh "file" with a transform, the current material for faces
   without one, the keyword's line on the objects, and rollback. */
static void test_nff_mesh(void **state)
{
    const char *path = "build_test_mesh.nff";
    FILE *f = fopen(path, "w");
    ggScene *s = ggSceneCreate(NULL);
    ggMeshInfo mi;
    ggError e;
    (void)state;
    assert_non_null(f);
    fprintf(f, "f 0.2 0.4 0.6 1 0 100000 0 0\n"
               "mesh \"" DATA "cube_le.ply\" scale 2 rotate z 90 translate 10 0 0\n"
               "s 0 0 5 1\n");
    fclose(f);
    assert_int_equal(ggSceneLoadFile(s, path, &e), GG_OK);
    assert_int_equal(ggSceneObjectCount(s), 2);
    assert_int_equal(ggSceneObjectKind(s, 0), GG_SHAPE_MESH);
    assert_int_equal(ggSceneObjectLine(s, 0), 2);
    assert_true(ggSceneMaterial(s, ggSceneObjectMaterial(s, 0)).color.b == 0.6);
    ggSceneGetMeshInfo(s, 0, &mi);
    /* x in [0, 1] -> scaled [0, 2] -> rotated to y in [0, 2], x in [-2, 0] -> x + 10 */
    assert_close(mi.lo.x, 8, 1e-12);
    assert_close(mi.hi.x, 10, 1e-12);
    assert_close(mi.hi.y, 2, 1e-12);
    assert_close(mi.hi.z, 2, 1e-12);
    /* an error in the mesh file fails the scene, which stays as it was */
    f = fopen(path, "w");
    fprintf(f, "s 0 0 0 1\nmesh \"" DATA "cube_le.ply\" scale 0\n");
    fclose(f);
    assert_int_equal(ggSceneLoadFile(s, path, &e), GG_ERROR_INVALID);
    assert_string_equal(e.message,
                        "build_test_mesh.nff:2:44: mesh: scale 0 makes the transform singular");
    assert_int_equal(ggSceneObjectCount(s), 2);
    assert_int_equal(ggSceneMeshCount(s), 1);
    f = fopen(path, "w");
    fprintf(f, "mesh \"no/such.obj\"\n");
    fclose(f);
    assert_int_equal(ggSceneLoadFile(s, path, &e), GG_ERROR_IO);
    assert_string_equal(e.message,
                        "build_test_mesh.nff:1:6: mesh: no/such.obj: No such file or directory");
    remove(path);
    /* only regular files are read: a FIFO is refused at once, never waited on */
    assert_int_equal(mkfifo("build_test_mesh.ply", 0600), 0);
    assert_int_equal(ggSceneLoadMesh(s, "build_test_mesh.ply", NULL, &e), GG_ERROR_IO);
    assert_string_equal(e.message, "build_test_mesh.ply: not a regular file");
    remove("build_test_mesh.ply");
    assert_int_equal(mkdir("build_test_dir.obj", 0700), 0);
    assert_int_equal(ggSceneLoadMesh(s, "build_test_dir.obj", NULL, &e), GG_ERROR_IO);
    assert_string_equal(e.message, "build_test_dir.obj: not a regular file");
    rmdir("build_test_dir.obj");
    ggSceneFree(s);
}

/* A model file as a scene: framed (camera, two lights); renders. */
static void test_model_as_scene(void **state)
{
    ggScene *s = ggSceneCreate(NULL);
    ggRenderOptions o;
    ggImage *img = NULL;
    ggError e;
    int x, y, lit = 0;
    (void)state;
    assert_int_equal(ggSceneLoadFile(s, DATA "cube.obj", &e), GG_OK);
    assert_int_equal(ggSceneLightCount(s), 2);
    assert_string_equal(ggSceneFileName(s), DATA "cube.obj");
    ggRenderOptionsDefault(&o);
    o.width = 32, o.height = 32, o.threads = 1;
    assert_int_equal(ggRender(s, &o, &img, NULL, &e), GG_OK);
    for (y = 0; y < 32; y++)
        for (x = 0; x < 32; x++) lit += ggImageGet(img, x, y).r > 0;
    assert_true(lit > 200);
    ggImageFree(img);
    ggSceneFree(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_obj_cube),
        cmocka_unit_test(test_obj_memory),
        cmocka_unit_test(test_obj_errors),
        cmocka_unit_test(test_obj_forms),
        cmocka_unit_test(test_obj_concave),
        cmocka_unit_test(test_obj_concave_quad),
        cmocka_unit_test(test_obj_rollback),
        cmocka_unit_test(test_ply_encodings),
        cmocka_unit_test(test_ply_errors),
        cmocka_unit_test(test_ply_binary_rest),
        cmocka_unit_test(test_ply_binary_index_bound),
        cmocka_unit_test(test_ply_ascii_lines),
        cmocka_unit_test(test_nff_mesh),
        cmocka_unit_test(test_model_as_scene),
        cmocka_unit_test(test_obj_groups),
        cmocka_unit_test(test_obj_label_limit),
        cmocka_unit_test(test_ply_values),
        cmocka_unit_test(test_obj_name_comments),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
