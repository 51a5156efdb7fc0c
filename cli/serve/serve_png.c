/* SPDX-License-Identifier: MIT */
/*
** serve_png.c -- PNG files in memory for `ggrt serve`, without a
** compressor: the image data go into stored deflate blocks (RFC 1951,
** section 3.2.4) inside a zlib stream (RFC 1950), which any PNG reader
** decodes (PNG specification, ISO/IEC 15948, sections 5 and 10). On a
** local connection the bytes cost less than compressing them would.
*/
#if defined(GG_HAVE_MHD)
#include "serve/serve.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static uint32_t crc_table[256];
static pthread_once_t crc_once = PTHREAD_ONCE_INIT;

static void crc_init(void)
{
    uint32_t n, k, c;
    for (n = 0; n < 256; n++) {
        for (c = n, k = 0; k < 8; k++) c = c & 1 ? 0xedb88320u ^ (c >> 1) : c >> 1;
        crc_table[n] = c;
    }
}

static uint32_t crc(const unsigned char *p, size_t n)
{
    uint32_t c = 0xffffffffu;
    size_t i;
    for (i = 0; i < n; i++) c = crc_table[(c ^ p[i]) & 0xff] ^ (c >> 8);
    return c ^ 0xffffffffu;
}

static unsigned char *be32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)(v >> 24), p[1] = (unsigned char)(v >> 16);
    p[2] = (unsigned char)(v >> 8), p[3] = (unsigned char)v;
    return p + 4;
}

/* Chunk of type t with n data bytes already at p + 8; returns its end. */
static unsigned char *chunk(unsigned char *p, const char *t, size_t n)
{
    be32(p, (uint32_t)n);
    memcpy(p + 4, t, 4);
    return be32(p + 8 + n, crc(p + 4, n + 4));
}

unsigned char *srv_png(const float *rgb, int w, int h, size_t *len)
{
    static const unsigned char sig[8] = {137, 80, 78, 71, 13, 10, 26, 10};
    size_t row, raw, blocks, total, i, done;
    unsigned char *out, *data, *p, *d;
    uint32_t a = 1, b = 0;
    int y;
    if (w <= 0 || h <= 0) return NULL;
    row = (size_t)w * 3 + 1, raw = row * (size_t)h, blocks = (raw + 65534) / 65535;
    total = 8 + (12 + 13) + (12 + 2 + raw + 5 * blocks + 4) + 12;
    out = malloc(total);
    data = malloc(raw);
    if (!out || !data) {
        free(out), free(data);
        return NULL;
    }
    pthread_once(&crc_once, crc_init);
    /* The bytes ggImageWritePNG writes (ggLinearToSRGB8), encoded into the
       last raw - h bytes, then each row moved down behind its filter
       byte: row y's destination ends before row y + 1's source begins. */
    ggLinearToSRGB8(rgb, data + h, raw - (size_t)h);
    for (y = 0; y < h; y++) {
        d = data + (size_t)y * row;
        d[0] = 0; /* filter type 0: none */
        memmove(d + 1, data + h + (size_t)y * (row - 1), row - 1);
    }
    /* Adler-32 (RFC 1950, 8.2), reduced every 5552 bytes as zlib does. */
    for (i = 0; i < raw;) {
        size_t e = raw - i > 5552 ? i + 5552 : raw;
        for (; i < e; i++) a += data[i], b += a;
        a %= 65521u, b %= 65521u;
    }
    memcpy(out, sig, 8);
    p = out + 8;
    be32(p + 8, (uint32_t)w), be32(p + 12, (uint32_t)h);
    p[16] = 8, p[17] = 2, p[18] = 0, p[19] = 0, p[20] = 0; /* 8-bit RGB, no interlace */
    p = chunk(p, "IHDR", 13);
    d = p + 8;
    *d++ = 0x78, *d++ = 0x01; /* zlib: deflate, 32K window, no dictionary */
    for (done = 0; done < raw;) {
        size_t n = raw - done > 65535 ? 65535 : raw - done;
        *d++ = done + n == raw ? 1 : 0; /* BFINAL on the last, BTYPE 00: stored */
        *d++ = (unsigned char)n, *d++ = (unsigned char)(n >> 8);
        *d++ = (unsigned char)~n, *d++ = (unsigned char)(~n >> 8);
        memcpy(d, data + done, n);
        d += n, done += n;
    }
    d = be32(d, b << 16 | a);
    free(data);
    p = chunk(p, "IDAT", (size_t)(d - (p + 8)));
    p = chunk(p, "IEND", 0);
    *len = (size_t)(p - out);
    return out;
}

#else
typedef int serve_png_unused;
#endif
