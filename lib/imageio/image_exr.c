/* SPDX-License-Identifier: MIT */
/*
** image_exr.c -- OpenEXR input and output through OpenEXR's C core.
**
** The core reports errors through a callback that would print to stderr by
** default; ours keeps the first message of the current call for ggError.
** File access goes through our own pread/pwrite callbacks on a descriptor
** we own, so the reader sees exactly the file ggImageRead opened and the
** writer writes into the temporary file of the atomic write.
*/
#include "image.h"

#include <errno.h>
#include <openexr.h>
#include <pthread.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* Channel counts beyond this are refused: every channel of a chunk is
   decompressed even when we only want R, G and B. */
#define EXR_MAX_CHANNELS 1024

typedef struct exr_io {
    int fd;
    int64_t size;  /* file size, for the reader's sanity checks */
    int io_errno;  /* errno of a failed pread/pwrite, 0 if none */
    char msg[256]; /* first message the core reported */
} exr_io;

static void on_error(exr_const_context_t ctxt, exr_result_t code, const char *msg)
{
    void *ud = NULL;
    exr_io *io;
    (void)code;
    if (!ctxt || exr_get_user_data(ctxt, &ud) != EXR_ERR_SUCCESS || !ud) return;
    io = ud;
    /* The first message names the cause; later ones are the callers
       reporting that something below them failed. */
    if (!io->msg[0]) snprintf(io->msg, sizeof io->msg, "%s", msg ? msg : "unknown error");
}

/* Writing: the core holds its context's lock while it reports an error
   (exr_write_header on a full disk), and exr_get_user_data takes that
   lock again, so on_error hung there for ever. A write reports nothing
   through the core: write_cb keeps its own message, and the codes say
   the rest. */
static void on_write_error(exr_const_context_t ctxt, exr_result_t code, const char *msg)
{
    (void)ctxt, (void)code, (void)msg;
}

static int64_t read_cb(exr_const_context_t ctxt, void *ud, void *buf, uint64_t sz, uint64_t off,
                       exr_stream_error_func_ptr_t error_cb)
{
    exr_io *io = ud;
    uint64_t done = 0;
    if (off > (uint64_t)INT64_MAX || sz > (uint64_t)INT64_MAX - off) {
        error_cb(ctxt, EXR_ERR_READ_IO, "read past any possible file end");
        return -1;
    }
    while (done < sz) {
        size_t want = sz - done > ((size_t)1 << 30) ? ((size_t)1 << 30) : (size_t)(sz - done);
        ssize_t r = pread(io->fd, (char *)buf + done, want, (off_t)(off + done));
        if (r < 0) {
            char ebuf[128];
            if (errno == EINTR) continue;
            io->io_errno = errno;
            error_cb(ctxt, EXR_ERR_READ_IO, "read failed: %s",
                     gg_image_strerror(errno, ebuf, sizeof ebuf));
            return -1;
        }
        if (r == 0) break; /* end of file: the core checks the count */
        done += (uint64_t)r;
    }
    return (int64_t)done;
}

static int64_t size_cb(exr_const_context_t ctxt, void *ud)
{
    (void)ctxt;
    return ((exr_io *)ud)->size;
}

static int64_t write_cb(exr_const_context_t ctxt, void *ud, const void *buf, uint64_t sz,
                        uint64_t off, exr_stream_error_func_ptr_t error_cb)
{
    exr_io *io = ud;
    uint64_t done = 0;
    while (done < sz) {
        size_t want = sz - done > ((size_t)1 << 30) ? ((size_t)1 << 30) : (size_t)(sz - done);
        ssize_t r = pwrite(io->fd, (const char *)buf + done, want, (off_t)(off + done));
        if (r <= 0) {
            char ebuf[128];
            if (r < 0 && errno == EINTR) continue;
            io->io_errno = r < 0 ? errno : EIO;
            if (!io->msg[0])
                snprintf(io->msg, sizeof io->msg, "write failed: %s",
                         gg_image_strerror(io->io_errno, ebuf, sizeof ebuf));
            error_cb(ctxt, EXR_ERR_WRITE_IO, "%s", io->msg);
            return -1;
        }
        done += (uint64_t)r;
    }
    return (int64_t)done;
}

static void init_context(exr_context_initializer_t *init, exr_io *io)
{
    exr_context_initializer_t def = EXR_DEFAULT_CONTEXT_INITIALIZER;
    *init = def;
    init->error_handler_fn = on_error;
    init->user_data = io;
}

/* ggError from a failed core call: the core's own message if it gave one. */
static int fail(const exr_io *io, exr_result_t rv, int code, const char *path, const char *what,
                ggError *err)
{
    char ebuf[128], lbuf[sizeof io->msg];
    const char *why =
        gg_image_lower(io->msg[0] ? io->msg : exr_get_default_error_message(rv), lbuf, sizeof lbuf);
    /* (3.1.5 also says "out of memory" for a compressed chunk that does
       not decompress: that is a corrupt file.) */
    if (rv == EXR_ERR_OUT_OF_MEMORY && !strstr(why, "decompress")) code = GG_ERROR_NOMEM;
    /* OpenEXR 3.1's C core cannot decompress DWAA/DWAB, for one. */
    if (rv == EXR_ERR_FEATURE_NOT_IMPLEMENTED) {
        code = GG_ERROR_UNSUPPORTED;
        what = "OpenEXR feature not supported";
    }
    if (io->io_errno) {
        code = GG_ERROR_IO;
        why = gg_image_strerror(io->io_errno, ebuf, sizeof ebuf);
    }
    return gg_error_set(err, code, "%s: %s: %s", path, what, why);
}

/* ---- reading ---------------------------------------------------------- */

typedef struct exr_reader {
    exr_context_t ctx;
    exr_io *io;
    const char *path;
    ggImage *img;
    int grey; /* reading a lone Y channel into R */
    exr_decode_pipeline_t dec;
    int dec_ready;
    const ggAllocator *alloc;
    const gg_image_budget *budget; /* NULL: only the GG_IMAGE_MAX_* limits */
    void *scratch;                 /* where channels we do not want are decoded to */
    size_t scratch_cap;
    const char *layer; /* read channels LAYER.R, .G, .B (NULL: R, G, B or Y) */
} exr_reader;

/* Where a channel goes within the RGB pixel, or -1 to skip it. */
static int channel_slot(const char *name, int grey)
{
    if (!name) return -1;
    if (grey) return strcmp(name, "Y") == 0 ? 0 : -1;
    if (strcmp(name, "R") == 0) return 0;
    if (strcmp(name, "G") == 0) return 1;
    if (strcmp(name, "B") == 0) return 2;
    return -1;
}

/* Where channel `name` of layer `layer` ("layer.R") goes within the RGB
   pixel, or -1; layer NULL: channel_slot. */
static int layer_slot(const char *name, const char *layer, int grey)
{
    size_t n;
    if (!layer) return channel_slot(name, grey);
    n = strlen(layer);
    if (!name || strncmp(name, layer, n) || name[n] != '.') return -1;
    return channel_slot(name + n + 1, 0);
}

/* Decode chunk ci, whose top-left pixel is (x, y) of the image. */
static int decode_chunk(exr_reader *r, const exr_chunk_info_t *ci, int64_t x, int64_t y,
                        ggError *err)
{
    ggImage *img = r->img;
    exr_result_t rv;
    int c;
    /* The core derives chunk sizes from the header, but a hostile file
       must not make us decode outside the image. */
    if (ci->width <= 0 || ci->height <= 0 || x < 0 || y < 0 || x + ci->width > img->width ||
        y + ci->height > img->height)
        return gg_error_set(err, GG_ERROR_PARSE,
                            "%s: invalid OpenEXR file: chunk %d (%d x %d at %d, %d) lies "
                            "outside the data window",
                            r->path, (int)ci->idx, (int)ci->width, (int)ci->height, (int)x, (int)y);
    /* An uncompressed chunk holds its pixels as they are: a shorter one is
       truncated, and the core (3.1) would leave the rest of its buffer
       uninitialised and decode it as pixels. A compressed chunk's
       decompressor checks the size it produces. */
    if ((ci->compression == EXR_COMPRESSION_NONE && ci->packed_size != ci->unpacked_size) ||
        (ci->packed_size == 0 && ci->unpacked_size > 0))
        return gg_error_set(err, GG_ERROR_PARSE,
                            "%s: invalid OpenEXR file: chunk %d holds %llu bytes, its pixels "
                            "take %llu",
                            r->path, (int)ci->idx, (unsigned long long)ci->packed_size,
                            (unsigned long long)ci->unpacked_size);
    if (r->dec_ready)
        rv = exr_decoding_update(r->ctx, 0, ci, &r->dec);
    else
        rv = exr_decoding_initialize(r->ctx, 0, ci, &r->dec);
    if (rv != EXR_ERR_SUCCESS)
        return fail(r->io, rv, GG_ERROR_PARSE, r->path, "invalid OpenEXR file", err);
    r->dec_ready = 1;
    /* OpenEXR 3.1.5 can crash on channels left NULL ("skip it", as its
       documentation allows) in some layouts, e.g. a tiled half file whose
       last channel is unused (found by fuzzing). So unwanted channels are
       decoded too, into a scratch buffer that is then ignored. */
    if (gg_mem_grow(r->alloc, &r->scratch, &r->scratch_cap, (size_t)ci->width * (size_t)ci->height,
                    sizeof(float)) != 0)
        return gg_error_set(err, GG_ERROR_NOMEM, "%s: out of memory", r->path);
    for (c = 0; c < r->dec.channel_count; c++) {
        exr_coding_channel_info_t *ch = &r->dec.channels[c];
        int slot = layer_slot(ch->channel_name, r->layer, r->grey);
        if (slot < 0 || ch->height <= 0 || ch->width <= 0) {
            ch->decode_to_ptr = (uint8_t *)r->scratch;
            ch->user_pixel_stride = (int32_t)sizeof(float);
            ch->user_line_stride = (int32_t)sizeof(float) * (ch->width > 0 ? ch->width : 1);
            ch->user_data_type = EXR_PIXEL_FLOAT;
            ch->user_bytes_per_element = (int16_t)sizeof(float);
            continue;
        }
        /* Decode straight into the interleaved image, converting to float. */
        ch->decode_to_ptr =
            (uint8_t *)(img->px + 3 * ((size_t)y * (size_t)img->width + (size_t)x) + slot);
        ch->user_pixel_stride = 3 * (int32_t)sizeof(float);
        ch->user_line_stride = 3 * (int32_t)sizeof(float) * img->width;
        ch->user_data_type = EXR_PIXEL_FLOAT;
        ch->user_bytes_per_element = (int16_t)sizeof(float);
    }
    rv = exr_decoding_choose_default_routines(r->ctx, 0, &r->dec);
    if (rv == EXR_ERR_SUCCESS) rv = exr_decoding_run(r->ctx, 0, &r->dec);
    if (rv != EXR_ERR_SUCCESS)
        return fail(r->io, rv, GG_ERROR_PARSE, r->path, "invalid OpenEXR file", err);
    return GG_OK;
}

static int read_scanlines(exr_reader *r, const exr_attr_box2i_t *dw, ggError *err)
{
    int32_t lpc = 0;
    int64_t y;
    exr_result_t rv = exr_get_scanlines_per_chunk(r->ctx, 0, &lpc);
    if (rv != EXR_ERR_SUCCESS || lpc < 1)
        return fail(r->io, rv, GG_ERROR_PARSE, r->path, "invalid OpenEXR file", err);
    for (y = dw->min.y; y <= dw->max.y; y += lpc) {
        exr_chunk_info_t ci;
        int rc;
        rv = exr_read_scanline_chunk_info(r->ctx, 0, (int)y, &ci);
        if (rv != EXR_ERR_SUCCESS)
            return fail(r->io, rv, GG_ERROR_PARSE, r->path, "invalid OpenEXR file", err);
        /* Scanline chunks carry their first line's absolute y. */
        rc = decode_chunk(r, &ci, 0, (int64_t)ci.start_y - dw->min.y, err);
        if (rc != GG_OK) return rc;
    }
    return GG_OK;
}

static int read_tiles(exr_reader *r, ggError *err)
{
    int32_t tw = 0, th = 0, lw = 0, lh = 0, nx, ny, tx, ty;
    exr_result_t rv = exr_get_tile_sizes(r->ctx, 0, 0, 0, &tw, &th);
    if (rv == EXR_ERR_SUCCESS) rv = exr_get_level_sizes(r->ctx, 0, 0, 0, &lw, &lh);
    if (rv != EXR_ERR_SUCCESS || tw < 1 || th < 1 || lw < 1 || lh < 1)
        return fail(r->io, rv, GG_ERROR_PARSE, r->path, "invalid OpenEXR file", err);
    nx = (int32_t)(((int64_t)lw + tw - 1) / tw);
    ny = (int32_t)(((int64_t)lh + th - 1) / th);
    for (ty = 0; ty < ny; ty++) {
        for (tx = 0; tx < nx; tx++) {
            exr_chunk_info_t ci;
            int rc;
            rv = exr_read_tile_chunk_info(r->ctx, 0, tx, ty, 0, 0, &ci);
            if (rv != EXR_ERR_SUCCESS)
                return fail(r->io, rv, GG_ERROR_PARSE, r->path, "invalid OpenEXR file", err);
            /* Tile positions count from the data window's corner; 3.1
               reports tile indices in start_x/start_y, so use ours. */
            rc = decode_chunk(r, &ci, (int64_t)tx * tw, (int64_t)ty * th, err);
            if (rc != GG_OK) return rc;
        }
    }
    return GG_OK;
}

/* Header checks, then the pixels of part 0. */
static int read_part(exr_reader *r, const ggAllocator *alloc, ggError *err)
{
    const exr_attr_chlist_t *chl = NULL;
    exr_attr_box2i_t dw;
    exr_storage_t storage;
    int32_t chunks = 0;
    int i, rc, rgb = 0, y = 0;
    exr_result_t rv;
    rv = exr_get_storage(r->ctx, 0, &storage);
    if (rv == EXR_ERR_SUCCESS) rv = exr_get_data_window(r->ctx, 0, &dw);
    if (rv == EXR_ERR_SUCCESS) rv = exr_get_channels(r->ctx, 0, &chl);
    if (rv != EXR_ERR_SUCCESS || !chl)
        return fail(r->io, rv, GG_ERROR_PARSE, r->path, "invalid OpenEXR file", err);
    if (storage != EXR_STORAGE_SCANLINE && storage != EXR_STORAGE_TILED)
        return gg_error_set(err, GG_ERROR_UNSUPPORTED, "%s: deep OpenEXR data is not supported",
                            r->path);
    rc = gg_image_check_size(r->path, (int64_t)dw.max.x - dw.min.x + 1,
                             (int64_t)dw.max.y - dw.min.y + 1, err);
    if (rc == GG_OK)
        rc = gg_image_check_budget(r->path, (int64_t)dw.max.x - dw.min.x + 1,
                                   (int64_t)dw.max.y - dw.min.y + 1, r->budget, err);
    if (rc != GG_OK) return rc;
    if (chl->num_channels > EXR_MAX_CHANNELS)
        return gg_error_set(err, GG_ERROR_LIMIT, "%s: %d channels exceed the limit of %d", r->path,
                            (int)chl->num_channels, EXR_MAX_CHANNELS);
    for (i = 0; i < chl->num_channels; i++) {
        const exr_attr_chlist_entry_t *e = &chl->entries[i];
        if (layer_slot(e->name.str, r->layer, 0) >= 0) rgb = 1;
        if (!r->layer && channel_slot(e->name.str, 1) >= 0) y = 1;
    }
    if (!rgb && !y && r->layer)
        return gg_error_set(err, GG_ERROR_UNSUPPORTED, "%s: no layer '%s' (channels %s.R, .G, .B)",
                            r->path, r->layer, r->layer);
    if (!rgb && !y)
        return gg_error_set(err, GG_ERROR_UNSUPPORTED, "%s: no R, G, B or Y channel", r->path);
    r->grey = !rgb;
    for (i = 0; i < chl->num_channels; i++) {
        const exr_attr_chlist_entry_t *e = &chl->entries[i];
        const char *nm = e->name.str ? e->name.str : "";
        /* Any channel, not only those read: every channel is decoded (into
           the scratch buffer if unwanted, see decode_chunk), and OpenEXR
           3.1.5's half-to-float unpackers ignore the sampling, writing a
           subsampled channel's lines in full past the buffer (a Y, RY, BY
           file in one-line chunks). */
        if (e->x_sampling != 1 || e->y_sampling != 1)
            return gg_error_set(err, GG_ERROR_UNSUPPORTED,
                                "%s: subsampled channel %s is not supported", r->path, nm);
        /* Y with chroma is a colour image: read as grey it would be wrong. */
        if (r->grey && (strcmp(nm, "RY") == 0 || strcmp(nm, "BY") == 0))
            return gg_error_set(err, GG_ERROR_UNSUPPORTED,
                                "%s: luminance/chroma (Y, RY, BY) images are not supported",
                                r->path);
    }
    /* The chunk offset table alone takes 8 bytes per chunk: a header that
       promises more chunks than the file could hold is truncated or
       hostile, and would make the core allocate a huge table. */
    rv = exr_get_chunk_count(r->ctx, 0, &chunks);
    if (rv != EXR_ERR_SUCCESS || chunks < 1)
        return fail(r->io, rv, GG_ERROR_PARSE, r->path, "invalid OpenEXR file", err);
    if ((int64_t)chunks * 8 > r->io->size)
        return gg_error_set(err, GG_ERROR_PARSE,
                            "%s: invalid OpenEXR file: truncated (%d chunks in %lld bytes)",
                            r->path, (int)chunks, (long long)r->io->size);
    r->img = ggImageCreate((int)(dw.max.x - dw.min.x + 1), (int)(dw.max.y - dw.min.y + 1), alloc);
    if (!r->img) return gg_error_set(err, GG_ERROR_NOMEM, "%s: out of memory", r->path);
    if (storage == EXR_STORAGE_TILED)
        rc = read_tiles(r, err);
    else
        rc = read_scanlines(r, &dw, err);
    if (rc == GG_OK && r->grey) {
        size_t n = (size_t)r->img->width * (size_t)r->img->height, k;
        for (k = 0; k < n; k++) r->img->px[3 * k + 1] = r->img->px[3 * k + 2] = r->img->px[3 * k];
    }
    return rc;
}

/* gg_image_read_exr, of layer `layer` (NULL: the image's own R, G, B). */
static int read_exr_layer(FILE *fp, const char *path, const char *layer, const ggAllocator *alloc,
                          const gg_image_budget *b, ggImage **out, ggError *err)
{
    exr_context_initializer_t init;
    exr_reader r;
    exr_io io;
    struct stat st;
    exr_result_t rv;
    int rc;
    memset(&io, 0, sizeof io);
    memset(&r, 0, sizeof r);
    io.fd = fileno(fp);
    if (fstat(io.fd, &st) != 0) {
        char ebuf[128];
        return gg_error_set(err, GG_ERROR_IO, "%s: cannot read: %s", path,
                            gg_image_strerror(errno, ebuf, sizeof ebuf));
    }
    io.size = (int64_t)st.st_size;
    init_context(&init, &io);
    init.read_fn = read_cb;
    init.size_fn = size_cb;
    /* A damaged chunk table is an error, not something to search around. */
    init.flags = EXR_CONTEXT_FLAG_DISABLE_CHUNK_RECONSTRUCTION;
    r.io = &io;
    r.path = path;
    r.alloc = alloc;
    r.budget = b;
    r.layer = layer;
    rv = exr_start_read(&r.ctx, path, &init);
    if (rv != EXR_ERR_SUCCESS) {
        rc = fail(&io, rv, GG_ERROR_PARSE, path, "invalid OpenEXR file", err);
        exr_finish(&r.ctx);
        return rc;
    }
    rc = read_part(&r, alloc, err);
    if (r.dec_ready) exr_decoding_destroy(r.ctx, &r.dec);
    gg_mem_free(alloc, r.scratch);
    exr_finish(&r.ctx);
    if (rc != GG_OK) {
        ggImageFree(r.img);
        return rc;
    }
    *out = r.img;
    return GG_OK;
}

int gg_image_read_exr(FILE *fp, const char *path, const ggAllocator *alloc,
                      const gg_image_budget *b, ggImage **out, ggError *err)
{
    return read_exr_layer(fp, path, NULL, alloc, b, out, err);
}

GG_API int ggImageReadEXRLayer(const char *path, const char *layer, const ggAllocator *alloc,
                               ggImage **out, ggError *err)
{
    FILE *fp;
    int rc;
    if (!path || !out)
        return gg_error_set(err, GG_ERROR_INVALID, "ggImageReadEXRLayer: NULL argument");
    rc = gg_file_open(path, NULL, &fp, NULL, err);
    if (rc != GG_OK) return rc;
    rc = read_exr_layer(fp, path, layer && layer[0] ? layer : NULL, alloc, NULL, out, err);
    fclose(fp);
    return rc;
}

/* ---- writing ---------------------------------------------------------- */

/* What a file holds: the image, whose size all share, and the pixels of
   it and its layers (names[0] NULL: the image's own R, G, B). Pixels, not
   images: a render's layers are written from its layer map in place. */
typedef struct exr_set {
    const ggImage *img;
    const float *const *px;
    const char *const *names;
    int n;
} exr_set;

/* The image and slot channel `name` is written from. */
static const float *channel_src(const exr_set *set, const char *name, int *slot)
{
    const char *dot = name ? strrchr(name, '.') : NULL;
    int i;
    for (i = 0; i < set->n; i++) {
        const char *nm = set->names[i];
        if (!nm ? !dot
                : dot && strlen(nm) == (size_t)(dot - name) && !strncmp(nm, name, strlen(nm)))
            break;
    }
    *slot = channel_slot(dot ? dot + 1 : name, 0);
    if (i == set->n || *slot < 0) *slot = 0, i = 0; /* not one of ours: cannot happen */
    return set->px[i];
}

/* ---- writing the pixels: chunks compressed in parallel, written in order ----

   zlib takes nearly all of a write (170-320 ms for a 1024 x 1024 render
   on one core), and the chunks (16 rows each) compress independently.
   Threads take the next chunk in turn and compress it; the file must
   hold the chunks in increasing y, so each waits for the chunk before
   its own to be written before writing (the pipeline's
   yield_until_ready_fn and write_fn). The file's bytes do not depend on
   the number of threads. */

/* What the threads share: the next chunk to take, the next to write and
   the first error. */
typedef struct exr_job {
    exr_context_t ctx;
    int part, y0, lpc, nchunks;
    const exr_set *set;
    pthread_mutex_t mu;
    pthread_cond_t turn;
    int next_take, next_write;
    exr_result_t rv;
} exr_job;

/* One thread's pipeline: the chunk it is on, and the core's own compress
   and write routines, which ours wrap. */
typedef struct exr_coder {
    exr_job *job;
    int chunk;
    exr_result_t (*compress)(exr_encode_pipeline_t *enc);
    exr_result_t (*write)(exr_encode_pipeline_t *enc);
} exr_coder;

int gg_image_exr_threads;

/* Threads for n chunks (gg_image_exr_threads, image.h). */
#define EXR_MAX_CODERS 8

static int coder_threads(int n)
{
    long t = gg_image_exr_threads;
    if (t <= 0) {
        t = sysconf(_SC_NPROCESSORS_ONLN);
        if (t > n / 4) t = n / 4;
    }
    if (t > EXR_MAX_CODERS) t = EXR_MAX_CODERS;
    return t < 1 ? 1 : (int)t;
}

static void job_fail(exr_job *job, exr_result_t rv)
{
    pthread_mutex_lock(&job->mu);
    if (job->rv == EXR_ERR_SUCCESS) job->rv = rv;
    pthread_cond_broadcast(&job->turn);
    pthread_mutex_unlock(&job->mu);
}

/* OpenEXR's ZIP encoder (3.1 as Debian ships it, and every release up to
   3.4.7) stores zlib's output when it is exactly as long as the raw chunk,
   while every reader takes a chunk whose stored size equals its raw size
   for a raw chunk: the pixels read back are not those written
   (AcademySoftwareFoundation/openexr#2306). Such a chunk is stored raw
   here, as a fixed encoder stores it; the encoder left the raw bytes in
   packed_buffer. */
static exr_result_t compress_guarded(exr_encode_pipeline_t *enc)
{
    const exr_coder *w = enc->encoding_user_data;
    exr_result_t rv = w->compress(enc);
    if (rv == EXR_ERR_SUCCESS && enc->compressed_bytes == enc->packed_bytes &&
        enc->compressed_buffer != enc->packed_buffer)
        memcpy(enc->compressed_buffer, enc->packed_buffer, enc->packed_bytes);
    return rv;
}

/* Wait until the chunks before this one are written (or one failed). */
static exr_result_t wait_turn(exr_encode_pipeline_t *enc)
{
    const exr_coder *w = enc->encoding_user_data;
    exr_job *job = w->job;
    exr_result_t rv;
    pthread_mutex_lock(&job->mu);
    while (job->next_write != w->chunk && job->rv == EXR_ERR_SUCCESS)
        pthread_cond_wait(&job->turn, &job->mu);
    rv = job->rv;
    pthread_mutex_unlock(&job->mu);
    return rv;
}

static exr_result_t write_in_turn(exr_encode_pipeline_t *enc)
{
    const exr_coder *w = enc->encoding_user_data;
    exr_job *job = w->job;
    exr_result_t rv = w->write(enc);
    if (rv != EXR_ERR_SUCCESS) return rv; /* the caller fails the job */
    pthread_mutex_lock(&job->mu);
    job->next_write++;
    pthread_cond_broadcast(&job->turn);
    pthread_mutex_unlock(&job->mu);
    return rv;
}

/* Point the pipeline's channels at the rows of chunk y (the images are
   the data window, whose top row is y0). */
static void coder_channels(exr_encode_pipeline_t *enc, const exr_set *set, int y)
{
    const ggImage *img = set->img;
    int c;
    for (c = 0; c < enc->channel_count; c++) {
        exr_coding_channel_info_t *ch = &enc->channels[c];
        int slot;
        const float *src = channel_src(set, ch->channel_name, &slot);
        ch->user_data_type = EXR_PIXEL_FLOAT;
        ch->user_bytes_per_element = (int16_t)sizeof(float);
        ch->user_pixel_stride = 3 * (int32_t)sizeof(float);
        ch->user_line_stride = 3 * (int32_t)sizeof(float) * img->width;
        ch->encode_from_ptr = (const uint8_t *)(src + 3 * (size_t)y * (size_t)img->width + slot);
    }
}

/* One thread: chunks taken in turn until none is left or one failed. */
static void *coder_run(void *arg)
{
    exr_coder *w = arg;
    exr_job *job = w->job;
    exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
    int ready = 0;
    for (;;) {
        exr_chunk_info_t ci;
        exr_result_t rv;
        int y;
        pthread_mutex_lock(&job->mu);
        w->chunk =
            job->rv == EXR_ERR_SUCCESS && job->next_take < job->nchunks ? job->next_take++ : -1;
        pthread_mutex_unlock(&job->mu);
        if (w->chunk < 0) break;
        y = w->chunk * job->lpc;
        rv = exr_write_scanline_chunk_info(job->ctx, job->part, job->y0 + y, &ci);
        if (rv == EXR_ERR_SUCCESS)
            rv = ready ? exr_encoding_update(job->ctx, job->part, &ci, &enc)
                       : exr_encoding_initialize(job->ctx, job->part, &ci, &enc);
        if (rv == EXR_ERR_SUCCESS) {
            coder_channels(&enc, job->set, y);
            if (!ready) rv = exr_encoding_choose_default_routines(job->ctx, job->part, &enc);
        }
        if (rv == EXR_ERR_SUCCESS && !ready) {
            w->compress = enc.compress_fn, w->write = enc.write_fn;
            if (enc.compress_fn) enc.compress_fn = compress_guarded;
            enc.yield_until_ready_fn = wait_turn, enc.write_fn = write_in_turn;
            enc.encoding_user_data = w;
        }
        ready = 1;
        if (rv == EXR_ERR_SUCCESS) rv = exr_encoding_run(job->ctx, job->part, &enc);
        if (rv != EXR_ERR_SUCCESS) {
            job_fail(job, rv);
            break;
        }
    }
    if (ready) exr_encoding_destroy(job->ctx, &enc);
    return NULL;
}

static int write_pixels(exr_context_t ctx, int part, const exr_set *set, int y0, exr_io *io,
                        const char *path, ggError *err)
{
    exr_job job;
    exr_coder w[EXR_MAX_CODERS];
    pthread_t th[EXR_MAX_CODERS];
    int32_t lpc = 0;
    int nt, started = 0, i;
    exr_result_t rv = exr_get_scanlines_per_chunk(ctx, part, &lpc);
    if (rv != EXR_ERR_SUCCESS || lpc < 1)
        return fail(io, rv != EXR_ERR_SUCCESS ? rv : EXR_ERR_INVALID_ARGUMENT, GG_ERROR_IO, path,
                    "cannot write OpenEXR", err);
    memset(&job, 0, sizeof job);
    job.ctx = ctx, job.part = part, job.y0 = y0, job.lpc = lpc, job.set = set;
    job.nchunks = (int)(((int64_t)set->img->height + lpc - 1) / lpc);
    job.rv = EXR_ERR_SUCCESS;
    if (pthread_mutex_init(&job.mu, NULL) != 0)
        return gg_error_set(err, GG_ERROR_NOMEM, "%s: cannot write OpenEXR: no mutex", path);
    if (pthread_cond_init(&job.turn, NULL) != 0) {
        pthread_mutex_destroy(&job.mu);
        return gg_error_set(err, GG_ERROR_NOMEM, "%s: cannot write OpenEXR: no condition", path);
    }
    nt = coder_threads(job.nchunks);
    for (i = 0; i < nt; i++) w[i].job = &job, w[i].chunk = -1, w[i].compress = w[i].write = NULL;
    /* This thread is coder 0; a thread that cannot start leaves its
       chunks to the others. */
    for (i = 1; i < nt; i++) {
        if (pthread_create(&th[started], NULL, coder_run, &w[i]) != 0) break;
        started++;
    }
    coder_run(&w[0]);
    for (i = 0; i < started; i++) pthread_join(th[i], NULL);
    rv = job.rv;
    pthread_cond_destroy(&job.turn);
    pthread_mutex_destroy(&job.mu);
    if (rv != EXR_ERR_SUCCESS) return fail(io, rv, GG_ERROR_IO, path, "cannot write OpenEXR", err);
    return GG_OK;
}

/* Attributes the writer sets itself, or that OpenEXR reserves. */
static const char *const reserved[] = {
    "channels",           "compression",       "dataWindow", "displayWindow", "lineOrder",
    "pixelAspectRatio",   "screenWindowCenter", "screenWindowWidth", "name", "type",
    "version",            "chunkCount",        "tiles",      NULL};

static int window_ok(int64_t x, int64_t y, int64_t w, int64_t h)
{
    return w >= 1 && h >= 1 && w <= GG_IMAGE_MAX_DIM && h <= GG_IMAGE_MAX_DIM &&
           x >= -GG_IMAGE_MAX_DIM && x <= GG_IMAGE_MAX_DIM && y >= -GG_IMAGE_MAX_DIM &&
           y <= GG_IMAGE_MAX_DIM;
}

/* The contract of ggImageWriteEXRHeader, checked before anything is
   created. */
static int check_header(const ggEXRHeader *h, ggError *err)
{
    int i, j, k;
    if (!window_ok(h->display_x, h->display_y, h->display_width, h->display_height) ||
        !window_ok(h->data_x, h->data_y, 1, 1))
        return gg_error_set(err, GG_ERROR_INVALID, "ggImageWriteEXRHeader: bad window");
    if (h->attr_count < 0 || h->attr_count > 256 || (h->attr_count > 0 && !h->attrs))
        return gg_error_set(err, GG_ERROR_INVALID, "ggImageWriteEXRHeader: bad attr_count %d",
                            h->attr_count);
    for (i = 0; i < h->attr_count; i++) {
        const char *n = h->attrs[i].name;
        if (!n || !h->attrs[i].value || !n[0] || strlen(n) > 31)
            return gg_error_set(err, GG_ERROR_INVALID,
                                "ggImageWriteEXRHeader: attribute %d: bad name or value", i);
        for (k = 0; reserved[k]; k++)
            if (strcmp(n, reserved[k]) == 0)
                return gg_error_set(err, GG_ERROR_INVALID,
                                    "ggImageWriteEXRHeader: attribute '%s' is reserved", n);
        for (j = 0; j < i; j++)
            if (strcmp(n, h->attrs[j].name) == 0)
                return gg_error_set(err, GG_ERROR_INVALID,
                                    "ggImageWriteEXRHeader: attribute '%s' repeated", n);
    }
    return GG_OK;
}

/* The required attributes: whole-image windows without h. */
static exr_result_t init_part(exr_context_t ctx, int part, const ggImage *img,
                              const ggEXRHeader *h)
{
    exr_attr_box2i_t disp, data;
    exr_attr_v2f_t center = {{{0.0f, 0.0f}}};
    exr_result_t rv;
    int i;
    if (!h)
        return exr_initialize_required_attr_simple(ctx, part, img->width, img->height,
                                                   EXR_COMPRESSION_ZIP);
    disp.min.x = h->display_x, disp.min.y = h->display_y;
    disp.max.x = h->display_x + h->display_width - 1;
    disp.max.y = h->display_y + h->display_height - 1;
    data.min.x = h->data_x, data.min.y = h->data_y;
    data.max.x = h->data_x + img->width - 1, data.max.y = h->data_y + img->height - 1;
    rv = exr_initialize_required_attr(ctx, part, &disp, &data, 1.0f, &center, 1.0f,
                                      EXR_LINEORDER_INCREASING_Y, EXR_COMPRESSION_ZIP);
    for (i = 0; i < h->attr_count && rv == EXR_ERR_SUCCESS; i++)
        rv = exr_attr_set_string(ctx, part, h->attrs[i].name, h->attrs[i].value);
    return rv;
}

static int write_exr(const exr_set *set, const ggEXRHeader *h, const char *path, ggError *err)
{
    static const char *const names[3] = {"R", "G", "B"};
    const ggImage *img = set->img;
    exr_context_initializer_t init;
    exr_context_t ctx = NULL;
    gg_image_tmp t;
    exr_io io;
    exr_result_t rv;
    int part = 0, c, rc;
    rc = gg_image_tmp_open(&t, path, err);
    if (rc != GG_OK) return rc;
    memset(&io, 0, sizeof io);
    io.fd = t.fd;
    init_context(&init, &io);
    init.error_handler_fn = on_write_error;
    init.write_fn = write_cb;
    /* zlib level 1: float pixels hardly compress better at higher levels
       (docs/performance.md, "Smaller things"). */
    init.zip_level = 1;
    rv = exr_start_write(&ctx, path, EXR_WRITE_FILE_DIRECTLY, &init);
    if (rv == EXR_ERR_SUCCESS) rv = exr_add_part(ctx, NULL, EXR_STORAGE_SCANLINE, &part);
    if (rv == EXR_ERR_SUCCESS) rv = init_part(ctx, part, img, h);
    for (c = 0; c < 3 * set->n && rv == EXR_ERR_SUCCESS; c++) {
        char name[64];
        const char *nm = set->names[c / 3];
        snprintf(name, sizeof name, "%s%s%s", nm ? nm : "", nm ? "." : "", names[c % 3]);
        rv = exr_add_channel(ctx, part, name, EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1);
    }
    if (rv == EXR_ERR_SUCCESS) rv = exr_write_header(ctx);
    if (rv != EXR_ERR_SUCCESS) {
        rc = fail(&io, rv, GG_ERROR_IO, path, "cannot write OpenEXR", err);
    } else {
        rc = write_pixels(ctx, part, set, h ? h->data_y : 0, &io, path, err);
    }
    /* exr_finish writes the chunk offset table, so it can fail too. */
    rv = exr_finish(&ctx);
    if (rc == GG_OK && rv != EXR_ERR_SUCCESS)
        rc = fail(&io, rv, GG_ERROR_IO, path, "cannot write OpenEXR", err);
    if (rc != GG_OK) {
        gg_image_tmp_abort(&t, NULL);
        return rc;
    }
    return gg_image_tmp_commit(&t, NULL, err);
}

/* One image: its own R, G, B (px holds its pixels). */
static exr_set single(const ggImage *img, const float **px)
{
    static const char *const none[1] = {NULL};
    exr_set set;
    px[0] = img->px;
    set.img = img, set.px = px, set.names = none, set.n = 1;
    return set;
}

GG_API int ggImageWriteEXR(const ggImage *img, const char *path, ggError *err)
{
    const float *px[1];
    exr_set set;
    if (!img || !path) return gg_error_set(err, GG_ERROR_INVALID, "ggImageWriteEXR: NULL argument");
    set = single(img, px);
    return write_exr(&set, NULL, path, err);
}

GG_API int ggImageWriteEXRHeader(const ggImage *img, const ggEXRHeader *h, const char *path,
                                 ggError *err)
{
    const float *px[1];
    exr_set set;
    int rc;
    if (!img || !path)
        return gg_error_set(err, GG_ERROR_INVALID, "ggImageWriteEXRHeader: NULL argument");
    if (h && (rc = check_header(h, err)) != GG_OK) return rc;
    set = single(img, px);
    return write_exr(&set, h, path, err);
}

/* A layer name: 1..GG_EXR_LAYER_NAME bytes of letters, digits, '_' and
   '-'. */
static int layer_name_ok(const char *n)
{
    size_t k;
    if (!n || !n[0] || strlen(n) > GG_EXR_LAYER_NAME) return 0;
    for (k = 0; n[k]; k++)
        if (!((n[k] >= 'a' && n[k] <= 'z') || (n[k] >= 'A' && n[k] <= 'Z') ||
              (n[k] >= '0' && n[k] <= '9') || n[k] == '_' || n[k] == '-'))
            return 0;
    return 1;
}

/* The n layer names of ggImageWriteEXRLayers (fn names the caller in the
   message), and then img's R, G, B and the layers px[1..n] written. */
static int write_layers(const char *fn, const ggImage *img, const float **px,
                        const char *const *names, int n, const ggEXRHeader *h, const char *path,
                        ggError *err)
{
    const char *nm[1 + GG_EXR_LAYERS_MAX];
    exr_set set;
    int i, j, rc;
    px[0] = img->px, nm[0] = NULL;
    for (i = 0; i < n; i++) {
        if (!layer_name_ok(names[i]))
            return gg_error_set(err, GG_ERROR_INVALID,
                                "%s: layer %d: a name is 1 to %d letters, digits, '_' or '-'", fn,
                                i + 1, GG_EXR_LAYER_NAME);
        for (j = 0; j < i; j++)
            if (!strcmp(names[i], names[j]))
                return gg_error_set(err, GG_ERROR_INVALID, "%s: layer name '%s' repeated", fn,
                                    names[i]);
        nm[i + 1] = names[i];
    }
    if (h && (rc = check_header(h, err)) != GG_OK) return rc;
    set.img = img, set.px = px, set.names = nm, set.n = n + 1;
    return write_exr(&set, h, path, err);
}

GG_API int ggImageWriteEXRLayers(const ggImage *img, const ggImage *const *layers,
                                 const char *const *names, int n, const ggEXRHeader *h,
                                 const char *path, ggError *err)
{
    static const char fn[] = "ggImageWriteEXRLayers";
    const float *px[1 + GG_EXR_LAYERS_MAX];
    int i;
    if (!img || !path || (n > 0 && (!layers || !names)))
        return gg_error_set(err, GG_ERROR_INVALID, "%s: NULL argument", fn);
    if (n < 0 || n > GG_EXR_LAYERS_MAX)
        return gg_error_set(err, GG_ERROR_INVALID, "%s: %d layers (0..%d)", fn, n,
                            GG_EXR_LAYERS_MAX);
    for (i = 0; i < n; i++) {
        if (!layers[i] || layers[i]->width != img->width || layers[i]->height != img->height)
            return gg_error_set(err, GG_ERROR_INVALID, "%s: layer %d is missing or not %dx%d", fn,
                                i + 1, img->width, img->height);
        px[i + 1] = layers[i]->px;
    }
    return write_layers(fn, img, px, names, n, h, path, err);
}

GG_API int ggImageWriteEXRLayerMap(const ggImage *img, const float *map, const char *const *names,
                                   int n, const ggEXRHeader *h, const char *path, ggError *err)
{
    static const char fn[] = "ggImageWriteEXRLayerMap";
    const float *px[1 + GG_EXR_LAYERS_MAX];
    int i;
    if (!img || !path || (n > 0 && (!map || !names)))
        return gg_error_set(err, GG_ERROR_INVALID, "%s: NULL argument", fn);
    if (n < 0 || n > GG_EXR_LAYERS_MAX)
        return gg_error_set(err, GG_ERROR_INVALID, "%s: %d layers (0..%d)", fn, n,
                            GG_EXR_LAYERS_MAX);
    for (i = 0; i < n; i++)
        px[i + 1] = map + (size_t)i * (size_t)img->width * (size_t)img->height * 3;
    return write_layers(fn, img, px, names, n, h, path, err);
}

/* ---- headers ---------------------------------------------------------- */

/* A string attribute not among those the writer sets itself (OpenEXR's
   core writes "type" too). */
static int listed(const exr_attribute_t *a)
{
    int k;
    if (a->type != EXR_ATTR_STRING || !a->string || !a->name) return 0;
    for (k = 0; reserved[k]; k++)
        if (strcmp(a->name, reserved[k]) == 0) return 0;
    return 1;
}

/* Copy the string attributes into one block: the array, then the texts. */
static int copy_attrs(exr_context_t ctx, const char *path, ggEXRHeader *out, ggError *err)
{
    int32_t n = 0, i;
    size_t bytes = 0;
    char *p;
    if (exr_get_attribute_count(ctx, 0, &n) != EXR_ERR_SUCCESS || n < 0) n = 0;
    for (i = 0; i < n; i++) {
        const exr_attribute_t *a = NULL;
        if (exr_get_attribute_by_index(ctx, 0, EXR_ATTR_LIST_FILE_ORDER, i, &a) != EXR_ERR_SUCCESS ||
            !a || !listed(a))
            continue;
        bytes += sizeof(ggEXRAttr) + strlen(a->name) + 1 + (size_t)a->string->length + 1;
        out->attr_count++;
    }
    if (!out->attr_count) return GG_OK;
    if (!(out->attrs = gg_mem_alloc(NULL, bytes)))
        return gg_error_set(err, GG_ERROR_NOMEM, "%s: out of memory", path);
    p = (char *)(out->attrs + out->attr_count);
    out->attr_count = 0;
    for (i = 0; i < n; i++) {
        const exr_attribute_t *a = NULL;
        ggEXRAttr *d = &out->attrs[out->attr_count];
        size_t len;
        if (exr_get_attribute_by_index(ctx, 0, EXR_ATTR_LIST_FILE_ORDER, i, &a) != EXR_ERR_SUCCESS ||
            !a || !listed(a))
            continue;
        len = strlen(a->name) + 1;
        memcpy(p, a->name, len), d->name = p, p += len;
        len = (size_t)a->string->length;
        if (len) memcpy(p, a->string->str, len);
        p[len] = '\0', d->value = p, p += len + 1;
        out->attr_count++;
    }
    return GG_OK;
}

static int read_windows(exr_context_t ctx, exr_io *io, const char *path, ggEXRHeader *out,
                        ggError *err)
{
    exr_attr_box2i_t disp, data;
    exr_result_t rv = exr_get_display_window(ctx, 0, &disp);
    if (rv == EXR_ERR_SUCCESS) rv = exr_get_data_window(ctx, 0, &data);
    if (rv != EXR_ERR_SUCCESS) return fail(io, rv, GG_ERROR_PARSE, path, "invalid OpenEXR file", err);
    if (!window_ok(disp.min.x, disp.min.y, (int64_t)disp.max.x - disp.min.x + 1,
                   (int64_t)disp.max.y - disp.min.y + 1) ||
        !window_ok(data.min.x, data.min.y, (int64_t)data.max.x - data.min.x + 1,
                   (int64_t)data.max.y - data.min.y + 1))
        return gg_error_set(err, GG_ERROR_PARSE, "%s: invalid OpenEXR file: window out of range",
                            path);
    out->display_x = disp.min.x, out->display_y = disp.min.y;
    out->display_width = disp.max.x - disp.min.x + 1;
    out->display_height = disp.max.y - disp.min.y + 1;
    out->data_x = data.min.x, out->data_y = data.min.y;
    out->data_width = data.max.x - data.min.x + 1, out->data_height = data.max.y - data.min.y + 1;
    return copy_attrs(ctx, path, out, err);
}

GG_API int ggImageReadEXRHeader(const char *path, ggEXRHeader *out, ggError *err)
{
    static const unsigned char magic[4] = {0x76, 0x2f, 0x31, 0x01};
    unsigned char head[4];
    exr_context_initializer_t init;
    exr_context_t ctx = NULL;
    exr_io io;
    FILE *fp;
    int64_t size = 0;
    exr_result_t rv;
    int rc;
    if (!path || !out) return gg_error_set(err, GG_ERROR_INVALID, "ggImageReadEXRHeader: NULL argument");
    memset(out, 0, sizeof *out);
    rc = gg_file_open(path, NULL, &fp, &size, err);
    if (rc != GG_OK) return rc;
    if (fread(head, 1, sizeof head, fp) != sizeof head || memcmp(head, magic, sizeof magic)) {
        fclose(fp);
        return gg_error_set(err, GG_ERROR_UNSUPPORTED, "%s: not an OpenEXR file", path);
    }
    memset(&io, 0, sizeof io);
    io.fd = fileno(fp);
    io.size = size;
    init_context(&init, &io);
    init.read_fn = read_cb;
    init.size_fn = size_cb;
    init.flags = EXR_CONTEXT_FLAG_DISABLE_CHUNK_RECONSTRUCTION;
    rv = exr_start_read(&ctx, path, &init);
    if (rv != EXR_ERR_SUCCESS)
        rc = fail(&io, rv, GG_ERROR_PARSE, path, "invalid OpenEXR file", err);
    else
        rc = read_windows(ctx, &io, path, out, err);
    exr_finish(&ctx);
    fclose(fp);
    if (rc != GG_OK) ggEXRHeaderFree(out);
    return rc;
}

GG_API void ggEXRHeaderFree(ggEXRHeader *h)
{
    if (!h) return;
    gg_mem_free(NULL, h->attrs);
    memset(h, 0, sizeof *h);
}

GG_API const char *ggEXRHeaderGet(const ggEXRHeader *h, const char *name)
{
    int i;
    if (!h || !name) return NULL;
    for (i = 0; i < h->attr_count; i++)
        if (h->attrs && strcmp(h->attrs[i].name, name) == 0) return h->attrs[i].value;
    return NULL;
}
