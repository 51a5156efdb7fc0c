/* SPDX-License-Identifier: MIT */
/*
** test_bytes.c -- bytes a careful parser decides about
** (docs/scene-format.md, "Bytes, decided on purpose"):
** a NUL byte (inside a number, an implicit expression, a comment) is an
** error at its line and column; a UTF-8 byte order mark and CR or CRLF line
** endings are accepted, with the same line numbers as LF; UTF-16 is
** refused; bytes that are not UTF-8 or are control characters appear in
** every message as \xHH (gg_text_escape), for NFF, OBJ and file names.
*/
#include "testutil.h"

#include "core.h"

#include <string.h>

static int load(ggScene *s, const char *text, size_t len, ggError *e)
{
    return ggSceneLoadString(s, text, len, "t.nff", e);
}

#define LOAD(s, lit, e) load((s), (lit), sizeof(lit) - 1, (e))

static void expect(const char *text, size_t len, int code, const char *msg)
{
    ggScene *s = ggSceneCreate(NULL);
    ggError e;
    assert_int_equal(load(s, text, len, &e), code);
    if (code != GG_OK) {
        assert_string_equal(e.message, msg);
        assert_int_equal(ggSceneObjectCount(s), 0);
    }
    ggSceneFree(s);
}
#define EXPECT(lit, code, msg) expect((lit), sizeof(lit) - 1, (code), (msg))

static void test_nul_bytes(void **state)
{
    (void)state;
    /* strtod would stop at the NUL and read 1. */
    EXPECT("s 0 0 1\0junk 1\n", GG_ERROR_PARSE, "t.nff:1:8: NUL byte in a text file");
    /* A C string would end the expression at the NUL. */
    EXPECT("s 0 0 0 1\nimplicit \"x^2 + y^2 - 1\0+ z\" -1 -1 -1 1 1 1\n", GG_ERROR_PARSE,
           "t.nff:2:24: NUL byte in a text file");
    EXPECT("# a comment \0\ns 0 0 0 1\n", GG_ERROR_PARSE, "t.nff:1:13: NUL byte in a text file");
    EXPECT("s 0 0 0 1\r\rs 0\0", GG_ERROR_PARSE, "t.nff:3:4: NUL byte in a text file");
}

static void test_bom_and_line_endings(void **state)
{
    static const char *const scenes[] = {
        "# one\ns 0 0 0 1\ns 1 2\n",
        "\xEF\xBB\xBF# one\ns 0 0 0 1\ns 1 2\n",
        "# one\r\ns 0 0 0 1\r\ns 1 2\r\n",
        "# one\rs 0 0 0 1\rs 1 2\r",
        "\xEF\xBB\xBF# one\rs 0 0 0 1\r\ns 1 2\n",
    };
    size_t i;
    (void)state;
    for (i = 0; i < sizeof scenes / sizeof scenes[0]; i++)
        expect(scenes[i], strlen(scenes[i]), GG_ERROR_PARSE,
               "t.nff:4:1: expected a number after 's', got end of file");
    /* The BOM takes no column; a comment ends at a lone CR. */
    EXPECT("\xEF\xBB\xBFx", GG_ERROR_PARSE, "t.nff:1:1: unknown keyword 'x'");
    EXPECT("# c\rs 0 0 0 1\r# c\r\rs 0 0 x 1", GG_ERROR_PARSE,
           "t.nff:5:7: expected a number after 's', got 'x'");
    EXPECT("texture \"a\rb\"\n", GG_ERROR_PARSE, "t.nff:1:9: unterminated string");
    EXPECT("\xEF\xBB\xBFs 0 0 0 1\r\ns 1 0 0 1\rs 2 0 0 1\n", GG_OK, "");
    EXPECT("\xFF\xFEs\0", GG_ERROR_UNSUPPORTED,
           "t.nff:1:1: UTF-16 text is not supported (convert the file to UTF-8)");
}

/* OBJ lines end the same ways. */
static void test_obj_line_endings(void **state)
{
    static const char *const objs[] = {
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nv 0 0 x\n",
        "v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 3\r\nv 0 0 x\r\n",
        "v 0 0 0\rv 1 0 0\rv 0 1 0\rf 1 2 3\rv 0 0 x\r",
        "\xEF\xBB\xBFv 0 0 0\rv 1 0 0\r\nv 0 1 \\\r0\nf 1 2 3\nv 0 0 x",
    };
    size_t i;
    (void)state;
    for (i = 0; i < sizeof objs / sizeof objs[0]; i++) {
        ggScene *s = ggSceneCreate(NULL);
        ggMeshOptions mo;
        ggError e;
        ggMeshOptionsDefault(&mo);
        mo.format = GG_MESH_FORMAT_OBJ;
        assert_int_equal(ggSceneLoadMeshMemory(s, objs[i], strlen(objs[i]), "m.obj", &mo, &e),
                         GG_ERROR_PARSE);
        assert_string_equal(e.message, i == 3 ? "m.obj:6:7: expected a coordinate, got 'x'"
                                              : "m.obj:5:7: expected a coordinate, got 'x'");
        /* Without the bad line: one triangle. */
        assert_int_equal(
            ggSceneLoadMeshMemory(s, objs[i], strlen(objs[i]) - (i == 3 ? 8 : 9), "m.obj", &mo, &e),
            0);
        ggSceneFree(s);
    }
}

/* The OBJ/MTL lexer (lib/load/textlex.c) skips a UTF-8 BOM, and the BOM
   takes no column there either: gg_lc_check_text must move the line start
   past it, or every column on line 1 is 3 too far (the NFF reader has a
   lexer of its own, tested above). Guards `c->ls = c->p` after the skip:
   without it "\xEF\xBB\xBFv 0 0 x" is reported at 1:10. The NUL check
   runs in the same function, before any statement. */
static void test_obj_bom_column(void **state)
{
    static const struct {
        const char *text;
        size_t len;
        const char *msg;
    } cases[] = {
        {"\xEF\xBB\xBFv 0 0 x", 10, "t.obj:1:7: expected a coordinate, got 'x'"},
        {"\xEF\xBB\xBF"
         "f 1 2 3\n",
         11, "t.obj:1:3: vertex index 1 is out of range (0 defined so far)"},
        {"\xEF\xBB\xBFv\0", 5, "t.obj:1:2: NUL byte in a text file"},
        /* line 2 is unaffected either way */
        {"\xEF\xBB\xBFv 0 0 0\nv 0 0 x", 18, "t.obj:2:7: expected a coordinate, got 'x'"},
    };
    size_t i;
    (void)state;
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        ggScene *s = ggSceneCreate(NULL);
        ggError e;
        assert_int_equal(ggSceneLoadMeshMemory(s, cases[i].text, cases[i].len, "t.obj", NULL, &e),
                         GG_ERROR_PARSE);
        assert_string_equal(e.message, cases[i].msg);
        ggSceneFree(s);
    }
}

static void test_messages_escape_bytes(void **state)
{
    ggScene *s = ggSceneCreate(NULL);
    ggMeshOptions mo;
    ggError e;
    (void)state;
    EXPECT("s 0 0 \xFF\xFE 1\n", GG_ERROR_PARSE,
           "t.nff:1:7: expected a number after 's', got '\\xFF\\xFE'");
    EXPECT("s 0 0 caf\xC3\xA9 1\n", GG_ERROR_PARSE,
           "t.nff:1:7: expected a number after 's', got 'caf\xC3\xA9'"); /* UTF-8 stays */
    EXPECT("\x01x 1\n", GG_ERROR_PARSE, "t.nff:1:1: unknown keyword '\\x01x'");
    /* A file name from the scene, and one from the caller. */
    assert_int_equal(LOAD(s, "texture \"t\xFF\x1B[2J.png\"\n", &e), GG_ERROR_IO);
    assert_string_equal(
        e.message, "t.nff:1:9: cannot read texture: t\\xFF\\x1B[2J.png: No such file or directory");
    assert_int_equal(ggSceneLoadFile(s, "no\xC0\n.nff", &e), GG_ERROR_IO);
    assert_string_equal(e.message, "no\\xC0\\x0A.nff: No such file or directory");
    /* The OBJ reader shows bytes the same way. */
    ggMeshOptionsDefault(&mo);
    mo.format = GG_MESH_FORMAT_OBJ;
    assert_int_equal(ggSceneLoadMeshMemory(s, "v 0 0 \xE9t\xE9\n", 10, "m\xFF.obj", &mo, &e),
                     GG_ERROR_PARSE);
    assert_string_equal(e.message, "m\\xFF.obj:1:7: expected a coordinate, got '\\xE9t\\xE9'");
    ggSceneFree(s);
}

static void test_escape_function(void **state)
{
    char buf[64];
    (void)state;
    assert_int_equal(gg_text_escape(buf, sizeof buf, "a\tb\x7f\xC3\xA9\xED\xA0\x80", 9), 24);
    assert_string_equal(buf, "a\\x09b\\x7F\xC3\xA9\\xED\\xA0\\x80"); /* no surrogates */
    gg_text_escape(buf, sizeof buf, "\xE0\x80\xAF|\xF4\x90\x80\x80|\xC0\xAF", 11);
    assert_string_equal(
        buf, "\\xE0\\x80\\xAF|\\xF4\\x90\\x80\\x80|\\xC0\\xAF"); /* overlong, > U+10FFFF */
    /* Cut at a whole character: never half of \xHH or of a UTF-8 sequence. */
    assert_int_equal(gg_text_escape(buf, 6, "ab\xFF", 3), 2);
    assert_string_equal(buf, "ab");
    assert_int_equal(gg_text_escape(buf, 4, "a\xC3\xA9", 3), 3);
    assert_int_equal(gg_text_escape(buf, 3, "a\xC3\xA9", 3), 1);
    /* A second pass changes nothing. */
    {
        char twice[64];
        gg_text_escape(buf, sizeof buf, "\x01\xFF\\x41\xC3\xA9", 8);
        gg_text_escape(twice, sizeof twice, buf, strlen(buf));
        assert_string_equal(twice, buf);
    }
}

/* A binary file is named by its first bytes, in NFF and OBJ alike, before
   any NUL byte or token is looked at; one byte off is no longer that
   format (and then a NUL byte, or a token, is the error). */
static void test_binary_files(void **state)
{
    static const struct {
        const char *bytes;
        size_t len;
        const char *kind;
    } files[] = {
        {"\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 16, "a PNG image"},
        {"\x76\x2f\x31\x01\x02\0\0\0", 8, "an OpenEXR image"},
        {"\xff\xd8\xff\xe0\0\x10JFIF", 10, "a JPEG image"},
        {"GIF89a\x01\0\x01\0", 10, "a GIF image"},
        {"GIF87a\x01\0\x01\0", 10, "a GIF image"},
        {"II*\0\x08\0\0\0", 8, "a TIFF image"},
        {"MM\0*\0\0\0\x08", 8, "a TIFF image"},
        {"RIFF\x24\0\0\0WEBPVP8 ", 16, "a WebP image"},
        {"glTF\x02\0\0\0", 8, "a binary glTF model"},
        {"\x1f\x8b\x08\0\0\0\0\0", 8, "gzip-compressed data"},
        {"PK\x03\x04\x14\0\0\0", 8, "a ZIP archive"},
        {"%PDF-1.7\n%\xe2\xe3", 12, "a PDF document"},
        {"\x7f" "ELF\x02\x01\x01\0", 8, "an executable (ELF)"},
    };
    size_t i;
    char want[200];
    (void)state;
    for (i = 0; i < sizeof files / sizeof files[0]; i++) {
        ggScene *s = ggSceneCreate(NULL);
        ggMeshOptions mo;
        ggError e;
        snprintf(want, sizeof want, "t.nff: this is %s, not a scene file (NFF, OBJ or PLY)",
                 files[i].kind);
        expect(files[i].bytes, files[i].len, GG_ERROR_PARSE, want);
        ggMeshOptionsDefault(&mo);
        mo.format = GG_MESH_FORMAT_OBJ;
        assert_int_equal(
            ggSceneLoadMeshMemory(s, files[i].bytes, files[i].len, "m.obj", &mo, &e),
            GG_ERROR_PARSE);
        snprintf(want, sizeof want, "m.obj: this is %s, not a text file (OBJ or MTL)",
                 files[i].kind);
        assert_string_equal(e.message, want);
        /* Without its first byte it is not that format any more. */
        assert_int_equal(load(s, files[i].bytes + 1, files[i].len - 1, &e), GG_ERROR_PARSE);
        assert_null(strstr(e.message, "this is"));
        ggSceneFree(s);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_nul_bytes),        cmocka_unit_test(test_bom_and_line_endings),
        cmocka_unit_test(test_obj_line_endings), cmocka_unit_test(test_messages_escape_bytes),
        cmocka_unit_test(test_obj_bom_column),   cmocka_unit_test(test_escape_function),
        cmocka_unit_test(test_binary_files),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
