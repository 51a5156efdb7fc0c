/* SPDX-License-Identifier: MIT */
/*
** fuzz_obj.c -- libFuzzer harness for the OBJ and MTL readers: the bytes
** as an OBJ file (the checks of fuzz_mesh.h), and the same bytes as an MTL
** library, which must parse or fail naming "fuzz.mtl:line:col". Under
** `make check` it replays tests/fuzz/corpus/obj/.
*/
#include "fuzz_mesh.h"

#include "mesh_int.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    gg_mtl_lib lib;
    ggError e;
    int rc;
    fuzz_mesh_one(data, size, "fuzz.obj");
    memset(&lib, 0, sizeof lib);
    memset(&e, 0, sizeof e);
    fuzz_cap = ((size_t)64 << 20) + 2000 * size;
    rc = gg_mtl_parse(&fuzz_alloc, &lib, (const char *)data, size, "fuzz.mtl", "", &e);
    fuzz_check(rc == GG_OK || !strncmp(e.message, "fuzz.mtl:", 9), "MTL errors name the place");
    gg_mtl_free(&fuzz_alloc, &lib);
    return 0;
}
