/* SPDX-License-Identifier: MIT */
// make_exr_fixtures.cpp -- writes the OpenEXR fixtures that OpenEXR 3.1's C
// core cannot write itself (DWAA/DWAB compression, ripmaps), with the C++
// library. Run once; the outputs are committed beside this file and checked
// by tests/unit/imageio/test_image_exr.c, which knows the same formulas.
//   g++ -I/usr/include/OpenEXR -I/usr/include/Imath make_exr_fixtures.cpp \
//       -lOpenEXR -lImath -o /tmp/mkexr && (cd tests/data && /tmp/mkexr)
#include <ImfArray.h>
#include <ImfHeader.h>
#include <ImfRgbaFile.h>
#include <ImfTiledRgbaFile.h>

using namespace Imf;

// Smooth, so the lossy DWA codecs stay close: must match test_image_exr.c.
static Rgba smooth(int x, int y)
{
    return Rgba(x / 16.0f, y / 16.0f, (x + y) / 32.0f, 1.0f);
}

// Exact in half; level (lx, ly) adds 10 (lx + ly) so a wrong level shows.
static Rgba level(int x, int y, int l)
{
    return Rgba(((x * 3 + y * 5) % 23) * 0.25f + 10 * l, ((x * 3 + y * 5 + 7) % 23) * 0.25f + 10 * l,
                ((x * 3 + y * 5 + 14) % 23) * 0.25f + 10 * l, 1.0f);
}

static void write_dwa(const char *name, Compression c)
{
    const int w = 16, h = 16;
    Array2D<Rgba> px(h, w);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) px[y][x] = smooth(x, y);
    RgbaOutputFile f(name, w, h, WRITE_RGB, 1, Imath::V2f(0, 0), 1, INCREASING_Y, c);
    f.setFrameBuffer(&px[0][0], 1, w);
    f.writePixels(h);
}

static void write_ripmap(const char *name)
{
    const int w = 9, h = 7;
    Header hdr(w, h, 1, Imath::V2f(0, 0), 1, INCREASING_Y, ZIP_COMPRESSION);
    TiledRgbaOutputFile f(name, hdr, WRITE_RGB, 4, 4, RIPMAP_LEVELS, ROUND_DOWN);
    for (int ly = 0; ly < f.numYLevels(); ly++)
        for (int lx = 0; lx < f.numXLevels(); lx++) {
            int lw = f.levelWidth(lx), lh = f.levelHeight(ly);
            Array2D<Rgba> px(lh, lw);
            for (int y = 0; y < lh; y++)
                for (int x = 0; x < lw; x++) px[y][x] = level(x, y, lx + ly);
            f.setFrameBuffer(&px[0][0], 1, lw);
            f.writeTiles(0, f.numXTiles(lx) - 1, 0, f.numYTiles(ly) - 1, lx, ly);
        }
}

int main()
{
    write_dwa("dwaa.exr", DWAA_COMPRESSION);
    write_dwa("dwab.exr", DWAB_COMPRESSION);
    write_ripmap("ripmap.exr");
    return 0;
}
