/* SPDX-License-Identifier: MIT */
/*
** fuzz_ply.c -- libFuzzer harness for the PLY reader (ascii and both
** binary encodings): the checks of fuzz_mesh.h on the bytes as a PLY file.
** Under `make check` it replays tests/fuzz/corpus/ply/.
*/
#include "fuzz_mesh.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_mesh_one(data, size, "fuzz.ply");
    return 0;
}
