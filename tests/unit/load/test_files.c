/* SPDX-License-Identifier: MIT */
/*
** test_files.c -- only regular files are read (docs/scene-format.md, "NFF"): a FIFO
** (with no writer, so a blocking open would wait for ever), a directory
** and a device as a scene, a texture, an image, a mesh and an MTL library
** get GG_ERROR_IO "...: not a regular file" at once. An alarm turns a
** block into a failure instead of a hung suite. An MTL library named
** again is not read again; MTL values are checked where they are.
*/
#include "testutil.h"

#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static char dir[] = "/tmp/gg_files_XXXXXX";
static char fifo[64], folder[64];

static int setup(void **state)
{
    (void)state;
    if (!mkdtemp(dir)) return -1;
    snprintf(fifo, sizeof fifo, "%s/fifo.nff", dir);
    snprintf(folder, sizeof folder, "%s/folder.png", dir);
    if (mkfifo(fifo, 0600) != 0 || mkdir(folder, 0700) != 0) return -1;
    alarm(60); /* a blocked open or read ends the run with SIGALRM */
    return 0;
}

static int teardown(void **state)
{
    char p[96];
    (void)state;
    alarm(0);
    remove(fifo);
    rmdir(folder);
    snprintf(p, sizeof p, "%s/t.nff", dir);
    remove(p);
    snprintf(p, sizeof p, "%s/t.obj", dir);
    remove(p);
    snprintf(p, sizeof p, "%s/t.mtl", dir);
    remove(p);
    rmdir(dir);
    return 0;
}

static void expect_refused(const char *path, const char *what)
{
    char want[160];
    ggScene *s = ggSceneCreate(NULL);
    ggImage *img = NULL;
    ggError e;
    snprintf(want, sizeof want, "%s: not a regular file", path);
    assert_int_equal(ggSceneLoadFile(s, path, &e), GG_ERROR_IO);
    assert_string_equal(e.message, want);
    assert_int_equal(ggImageRead(path, NULL, &img, &e), GG_ERROR_IO);
    assert_string_equal(e.message, want);
    assert_null(img);
    assert_int_equal(ggSceneLoadMesh(s, path, NULL, &e), GG_ERROR_IO);
    assert_string_equal(e.message, want);
    ggSceneFree(s);
    (void)what;
}

static void test_fifo(void **state)
{
    (void)state;
    expect_refused(fifo, "FIFO");
}
static void test_directory(void **state)
{
    (void)state;
    expect_refused(folder, "directory");
}
static void test_devices(void **state)
{
    (void)state;
    expect_refused("/dev/null", "character device");
    expect_refused("/dev/zero", "character device (endless)");
}

static void write_file(const char *name, const char *text)
{
    char p[96];
    FILE *f;
    snprintf(p, sizeof p, "%s/%s", dir, name);
    f = fopen(p, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

/* Named from a scene file: the error has the scene's place. */
static void test_named_by_scenes(void **state)
{
    char p[96], want[256];
    ggScene *s = ggSceneCreate(NULL);
    ggError e;
    ggMeshInfo mi;
    (void)state;
    write_file("t.nff", "texture \"fifo.nff\"\ns 0 0 0 1\n");
    snprintf(p, sizeof p, "%s/t.nff", dir);
    assert_int_equal(ggSceneLoadFile(s, p, &e), GG_ERROR_IO);
    snprintf(want, sizeof want, "%s:1:9: cannot read texture: %s: not a regular file", p, fifo);
    assert_string_equal(e.message, want);
    write_file("t.nff", "mesh \"folder.png\"\n");
    assert_int_equal(ggSceneLoadFile(s, p, &e), GG_ERROR_IO);
    snprintf(want, sizeof want, "%s:1:6: mesh: %s: not a regular file", p, folder);
    assert_string_equal(e.message, want);
    assert_int_equal(ggSceneObjectCount(s), 0);
    /* An OBJ whose MTL library is a FIFO, and one whose map_Kd texture is:
       warnings, the mesh loads. */
    write_file("t.obj", "mtllib fifo.nff\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    snprintf(p, sizeof p, "%s/t.obj", dir);
    assert_int_equal(ggSceneLoadMesh(s, p, NULL, &e), GG_OK);
    assert_int_equal(ggSceneGetMeshInfo(s, 0, &mi), GG_OK);
    assert_non_null(strstr(mi.warning, "cannot read the material library 'fifo.nff'"));
    write_file("t.mtl", "newmtl a\nKd 1 0 0\nmap_Kd fifo.nff\n");
    write_file("t.obj", "mtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nusemtl a\n"
                        "f 1/1 2/1 3/1\n");
    assert_int_equal(ggSceneLoadMesh(s, p, NULL, &e), GG_OK);
    assert_int_equal(ggSceneGetMeshInfo(s, 1, &mi), GG_OK);
    snprintf(want, sizeof want, "texture not used (%s: not a regular file)", fifo);
    assert_non_null(strstr(mi.warning, want));
    ggSceneFree(s);
}

/* An MTL library is read once, however often and however it is named: an
   OBJ that is its own library, named on 50 lines and once as ./t.obj,
   counts its statements once (the 3 MTL lines the OBJ reader skips, the 56
   lines after the last newmtl the MTL reader skips); read at every mtllib
   line they were 2859, and 4000 lines of an 88 KB file took 1.16 GB. */
static void test_mtllib_once(void **state)
{
    char p[96];
    ggScene *s = ggSceneCreate(NULL);
    ggError e;
    ggMeshInfo mi;
    FILE *f;
    int i;
    (void)state;
    snprintf(p, sizeof p, "%s/t.obj", dir);
    f = fopen(p, "w");
    assert_non_null(f);
    fputs("newmtl a\nKd 1 0 0\nnewmtl b\n", f);
    for (i = 0; i < 50; i++) fputs("mtllib t.obj\n", f);
    fputs("mtllib ./t.obj\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl b\nf 1 2 3\n", f);
    fclose(f);
    assert_int_equal(ggSceneLoadMesh(s, p, NULL, &e), GG_OK);
    assert_int_equal(ggSceneGetMeshInfo(s, 0, &mi), GG_OK);
    assert_int_equal(mi.ignored, 59);
    assert_int_equal(mi.warnings, 0);
    assert_int_equal(ggSceneMaterialCount(s), 1);
    ggSceneFree(s);
}

/* MTL values: nan and inf are no colour (not an unsupported colour
   form), a negative component is named where it is, and illum is a
   whole number (3.9 was read as 3). */
static void test_mtl_values(void **state)
{
    static const struct {
        const char *line, *msg;
        int code;
    } bad[] = {
        {"Kd nan", "2:4: expected a colour, got 'nan'", GG_ERROR_PARSE},
        {"Kd inf", "2:4: expected a colour, got 'inf'", GG_ERROR_PARSE},
        {"Kd 0x1", "2:4: expected a colour, got '0x1'", GG_ERROR_PARSE},
        {"Kd 0.5 nan 1", "2:8: expected a colour, got 'nan'", GG_ERROR_PARSE},
        {"Kd spectral a.spd", "2:4: Kd: only r g b colours are supported", GG_ERROR_UNSUPPORTED},
        {"Kd 0.5 0.5 -1", "2:12: Kd must not be negative", GG_ERROR_PARSE},
        {"Ks -1", "2:4: Ks must not be negative", GG_ERROR_PARSE},
        {"illum 3.9", "2:7: illum must be a whole number, got 3.9", GG_ERROR_PARSE},
        {"illum 11", "2:7: illum must be in [0, 10], got 11", GG_ERROR_PARSE},
    };
    char p[96], mtl[96], text[96], want[256];
    size_t i;
    (void)state;
    snprintf(p, sizeof p, "%s/t.obj", dir);
    snprintf(mtl, sizeof mtl, "%s/t.mtl", dir);
    write_file("t.obj", "mtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n");
    for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        ggScene *s = ggSceneCreate(NULL);
        ggError e;
        int rc;
        snprintf(text, sizeof text, "newmtl a\n%s\n", bad[i].line);
        write_file("t.mtl", text);
        snprintf(want, sizeof want, "%s:%s", mtl, bad[i].msg);
        rc = ggSceneLoadMesh(s, p, NULL, &e);
        if (rc != bad[i].code || strcmp(e.message, want))
            print_error("%s: got %d '%s'\n", bad[i].line, rc, rc ? e.message : "");
        assert_int_equal(rc, bad[i].code);
        assert_string_equal(e.message, want);
        ggSceneFree(s);
    }
}

/* A reader of the caller's that fails without writing its ggError, or
   with a status of its own: the load says so, with a GG_ERROR_ code. */
static int quiet_reader(void *ud, const char *path, const ggAllocator *a, ggImage **out,
                        ggError *err)
{
    (void)path, (void)a, (void)out, (void)err;
    return *(const int *)ud;
}

static void test_reader_without_message(void **state)
{
    static const int io = GG_ERROR_IO, own = 42;
    char p[96], want[256];
    ggScene *s = ggSceneCreate(NULL);
    ggError e;
    ggMeshInfo mi;
    (void)state;
    ggSceneSetImageReader(s, quiet_reader, (void *)&io);
    write_file("t.nff", "texture \"a.png\"\ns 0 0 0 1\n");
    snprintf(p, sizeof p, "%s/t.nff", dir);
    memset(&e, 'Z', sizeof e); /* what the reader would have left */
    assert_int_equal(ggSceneLoadFile(s, p, &e), GG_ERROR_IO);
    snprintf(want, sizeof want,
             "%s:1:9: cannot read texture: %s/a.png: the image reader failed (status 4) "
             "without a message",
             p, dir);
    assert_string_equal(e.message, want);
    ggSceneSetImageReader(s, quiet_reader, (void *)&own);
    assert_int_equal(ggSceneLoadFile(s, p, &e), GG_ERROR_IO);
    assert_non_null(strstr(e.message, "(status 42) without a message"));
    /* an OBJ's map_Kd: the warning has the message */
    write_file("t.mtl", "newmtl a\nKd 1 0 0\nmap_Kd b.png\n");
    write_file("t.obj", "mtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nusemtl a\n"
                        "f 1/1 2/1 3/1\n");
    snprintf(p, sizeof p, "%s/t.obj", dir);
    assert_int_equal(ggSceneLoadMesh(s, p, NULL, &e), GG_OK);
    assert_int_equal(ggSceneGetMeshInfo(s, 0, &mi), GG_OK);
    snprintf(want, sizeof want,
             "texture not used (%s/b.png: the image reader failed (status 42) without a "
             "message)",
             dir);
    assert_non_null(strstr(mi.warning, want));
    ggSceneFree(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fifo),
        cmocka_unit_test(test_directory),
        cmocka_unit_test(test_devices),
        cmocka_unit_test(test_named_by_scenes),
        cmocka_unit_test(test_mtllib_once),
        cmocka_unit_test(test_mtl_values),
        cmocka_unit_test(test_reader_without_message),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
