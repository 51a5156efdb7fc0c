/* SPDX-License-Identifier: MIT */
/*
** image_io.c -- choosing the image format (magic bytes to read, extension
** to write) and the temporary-file dance that makes writes atomic.
*/
#include "image.h"

#include <errno.h>
#include <fcntl.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

const char *gg_image_strerror(int errnum, char *buf, size_t n)
{
    /* The XSI strerror_r (we build with _POSIX_C_SOURCE=200809L) returns an
       int; strerror itself is not thread-safe. */
    if (strerror_r(errnum, buf, n) != 0) snprintf(buf, n, "error %d", errnum);
    return buf;
}

const char *gg_image_lower(const char *msg, char *buf, size_t n)
{
    snprintf(buf, n, "%s", msg ? msg : "");
    /* a capitalised word, not an acronym: "End of file" but not "EXR" */
    if (buf[0] >= 'A' && buf[0] <= 'Z' && buf[1] >= 'a' && buf[1] <= 'z') buf[0] += 'a' - 'A';
    return buf;
}

GG_API int ggImageRead(const char *path, const ggAllocator *alloc, ggImage **out, ggError *err)
{
    return gg_image_read_budget(path, alloc, NULL, out, err);
}

int gg_image_read_budget(const char *path, const ggAllocator *alloc, const gg_image_budget *b,
                         ggImage **out, ggError *err)
{
    static const unsigned char png_magic[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    static const unsigned char exr_magic[4] = {0x76, 0x2f, 0x31, 0x01};
    unsigned char head[8];
    char ebuf[128];
    size_t got;
    FILE *fp;
    int rc;
    if (!path || !out) return gg_error_set(err, GG_ERROR_INVALID, "ggImageRead: NULL argument");
    rc = gg_file_open(path, NULL, &fp, NULL, err);
    if (rc != GG_OK) return rc;
    got = fread(head, 1, sizeof head, fp);
    if (got < sizeof head && ferror(fp)) {
        rc = gg_error_set(err, GG_ERROR_IO, "%s: cannot read: %s", path,
                          gg_image_strerror(errno, ebuf, sizeof ebuf));
        fclose(fp);
        return rc;
    }
    if (fseek(fp, 0, SEEK_SET) != 0) {
        rc = gg_error_set(err, GG_ERROR_IO, "%s: cannot seek: %s", path,
                          gg_image_strerror(errno, ebuf, sizeof ebuf));
        fclose(fp);
        return rc;
    }
    if (got >= sizeof png_magic && memcmp(head, png_magic, sizeof png_magic) == 0)
        rc = gg_image_read_png(fp, path, alloc, b, out, err);
    else if (got >= sizeof exr_magic && memcmp(head, exr_magic, sizeof exr_magic) == 0)
        rc = gg_image_read_exr(fp, path, alloc, b, out, err);
    else
        rc = gg_error_set(err, GG_ERROR_UNSUPPORTED, "%s: not a PNG or OpenEXR file", path);
    fclose(fp);
    return rc;
}

static int has_extension(const char *path, const char *ext)
{
    size_t n = strlen(path), m = strlen(ext), i;
    if (n < m) return 0;
    for (i = 0; i < m; i++) {
        char c = path[n - m + i];
        if (c >= 'A' && c <= 'Z') c = (char)(c - 'A' + 'a');
        if (c != ext[i]) return 0;
    }
    return 1;
}

GG_API int ggImageWrite(const ggImage *img, const char *path, ggError *err)
{
    if (!img || !path) return gg_error_set(err, GG_ERROR_INVALID, "ggImageWrite: NULL argument");
    if (has_extension(path, ".png")) return ggImageWritePNG(img, path, err);
    if (has_extension(path, ".exr")) return ggImageWriteEXR(img, path, err);
    return gg_error_set(err, GG_ERROR_UNSUPPORTED, "%s: unknown image extension (use .png or .exr)",
                        path);
}

/* At most this many bytes of the file's own name go into its temporary
   one, so that the suffix fits in a name of NAME_MAX (255) bytes. */
#define TMP_NAME_KEEP 200

int gg_image_tmp_open(gg_image_tmp *t, const char *path, ggError *err)
{
    char ebuf[128];
    const char *slash = strrchr(path, '/'), *base = slash ? slash + 1 : path;
    size_t n = strlen(path), keep = (size_t)(base - path) + strlen(base);
    struct stat st;
    int attempt, e = 0;
    t->path = path;
    t->fd = -1;
    if (keep - (size_t)(base - path) > TMP_NAME_KEEP) keep = (size_t)(base - path) + TMP_NAME_KEEP;
    t->tmp = gg_mem_alloc(NULL, n + 48);
    if (!t->tmp) return gg_error_set(err, GG_ERROR_NOMEM, "%s: out of memory", path);
    /* mkstemp would create the file 0600; an image should get the usual
       0666 & ~umask, so pick names ourselves and let O_EXCL decide. The
       process id, the address of t (distinct for threads writing at the
       same time) and the clock make collisions rare; no shared counter, so
       no data race. */
    for (attempt = 0; attempt < 100; attempt++) {
        struct timespec ts;
        clock_gettime(CLOCK_REALTIME, &ts);
        snprintf(t->tmp, n + 48, "%.*s.tmp%ld.%lx.%ld", (int)keep, path, (long)getpid(),
                 (unsigned long)(uintptr_t)t & 0xffffffUL, (long)(ts.tv_nsec % 1000000) + attempt);
        t->fd = open(t->tmp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (t->fd >= 0) {
            /* A file replaced keeps its permissions: a private one stays
               private (best effort: a file of another owner cannot). */
            if (stat(path, &st) == 0 && S_ISREG(st.st_mode))
                (void)fchmod(t->fd, st.st_mode & 07777);
            return GG_OK;
        }
        e = errno;
        if (e != EEXIST) break;
    }
    gg_mem_free(NULL, t->tmp);
    t->tmp = NULL;
    return gg_error_set(err, GG_ERROR_IO, "%s: cannot create temporary file: %s", path,
                        gg_image_strerror(e, ebuf, sizeof ebuf));
}

void gg_image_tmp_abort(gg_image_tmp *t, FILE *fp)
{
    if (fp)
        fclose(fp);
    else if (t->fd >= 0)
        close(t->fd);
    t->fd = -1;
    if (t->tmp) {
        unlink(t->tmp);
        gg_mem_free(NULL, t->tmp);
        t->tmp = NULL;
    }
}

int gg_image_tmp_commit(gg_image_tmp *t, FILE *fp, ggError *err)
{
    char ebuf[128];
    const char *what = NULL;
    int e = 0;
    if (fp && (fflush(fp) != 0 || ferror(fp))) {
        e = errno ? errno : EIO;
        what = "cannot write";
    }
    /* fsync so a crash after the rename cannot leave an empty file behind
       the new name; EINVAL means the file system has nothing to sync. */
    if (!what && fsync(t->fd) != 0 && errno != EINVAL) {
        e = errno;
        what = "cannot write";
    }
    if (fp) {
        if (fclose(fp) != 0 && !what) {
            e = errno;
            what = "cannot write";
        }
    } else if (close(t->fd) != 0 && !what) {
        e = errno;
        what = "cannot write";
    }
    t->fd = -1;
    if (!what && rename(t->tmp, t->path) != 0) {
        e = errno;
        what = "cannot rename temporary file into place";
    }
    if (what) {
        unlink(t->tmp);
        gg_mem_free(NULL, t->tmp);
        t->tmp = NULL;
        return gg_error_set(err, GG_ERROR_IO, "%s: %s: %s", t->path, what,
                            gg_image_strerror(e, ebuf, sizeof ebuf));
    }
    gg_mem_free(NULL, t->tmp);
    t->tmp = NULL;
    return GG_OK;
}
