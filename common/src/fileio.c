/* fileio.c: how every reader opens its input and every writer replaces its
 * output (sss/fileio.h has the policy; docs/robustness.md, "Paths";
 * docs/format.md §7 for the atomic write). */
#define _POSIX_C_SOURCE 200809L
#define _XOPEN_SOURCE 700 /* realpath */

#include "sss/fileio.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

/* What a file that is not a regular one is, for messages. */
static const char *kind_of(mode_t m)
{
    if (S_ISDIR(m)) return "a directory";
    if (S_ISFIFO(m)) return "a FIFO";
    if (S_ISCHR(m)) return "a character device";
    if (S_ISBLK(m)) return "a block device";
    if (S_ISSOCK(m)) return "a socket";
    if (S_ISLNK(m)) return "a symbolic link";
    return "not a regular file";
}

static char *dup_str(const char *s)
{
    size_t n = strlen(s) + 1;
    char *d = malloc(n);
    if (d) memcpy(d, s, n);
    return d;
}

/* ---- reading ---------------------------------------------------------- */

sss_result sss_input_open(const char *path, int *fd, uint64_t *size, sss_error *err)
{
    *fd = -1;
    *size = 0;
    if (!path || !*path) return sss_fail(err, SSS_ERR_ARG, "empty input path");
    /* O_NONBLOCK: opening a FIFO for reading would otherwise wait for a
     * writer forever, before any check could run */
    int f = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (f < 0) return sss_fail(err, SSS_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    struct stat st;
    if (fstat(f, &st) != 0) {
        int e = errno;
        close(f);
        return sss_fail(err, SSS_ERR_IO, "%s: cannot stat: %s", path, strerror(e));
    }
    if (!S_ISREG(st.st_mode)) {
        close(f);
        return sss_fail(err, SSS_ERR_IO, "%s: not a regular file (%s)", path, kind_of(st.st_mode));
    }
    int fl = fcntl(f, F_GETFL);
    if (fl < 0 || fcntl(f, F_SETFL, fl & ~O_NONBLOCK) != 0) {
        int e = errno;
        close(f);
        return sss_fail(err, SSS_ERR_IO, "%s: cannot read: %s", path, strerror(e));
    }
    if (st.st_size < 0) {
        close(f);
        return sss_fail(err, SSS_ERR_IO, "%s: cannot stat: negative size", path);
    }
    *fd = f;
    *size = (uint64_t)st.st_size;
    return SSS_OK;
}

sss_result sss_input_read_all(const char *path, uint64_t max_bytes, char **buf, size_t *len, sss_error *err)
{
    *buf = NULL;
    *len = 0;
    int fd;
    uint64_t size;
    sss_result r = sss_input_open(path, &fd, &size, err);
    if (r != SSS_OK) return r;
    if ((max_bytes && size > max_bytes) || size >= SIZE_MAX) {
        close(fd);
        return sss_fail(err, SSS_ERR_NOMEM, "%s: %llu bytes, more than the %llu this reader takes", path,
                        (unsigned long long)size, (unsigned long long)(max_bytes ? max_bytes : SIZE_MAX - 1));
    }
    char *b = malloc((size_t)size + 1);
    if (!b) {
        close(fd);
        return sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory for %llu bytes", path, (unsigned long long)size);
    }
    size_t got = 0;
    while (got < size) {
        size_t chunk = size - got > ((size_t)1 << 30) ? ((size_t)1 << 30) : (size_t)size - got;
        ssize_t n = read(fd, b + got, chunk);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            int e = n < 0 ? errno : 0;
            close(fd);
            free(b);
            if (n == 0)
                return sss_fail(err, SSS_ERR_IO, "%s: file shrank while reading (%zu of %llu bytes)", path, got,
                                (unsigned long long)size);
            return sss_fail(err, SSS_ERR_IO, "%s: read failed: %s", path, strerror(e));
        }
        got += (size_t)n;
    }
    close(fd);
    b[got] = 0;
    *buf = b;
    *len = got;
    return SSS_OK;
}

/* ---- writing ---------------------------------------------------------- */

sss_result sss_output_check(const char *path, const sss_inputs *in, char **target, sss_error *err)
{
    if (target) *target = NULL;
    if (!path || !*path) return sss_fail(err, SSS_ERR_ARG, "empty output path");
    struct stat ls, st;
    char *t = NULL;
    int exists = 1;
    if (lstat(path, &ls) != 0) {
        if (errno != ENOENT) return sss_fail(err, SSS_ERR_IO, "%s: cannot write: %s", path, strerror(errno));
        exists = 0;
        t = dup_str(path);
    } else if (S_ISLNK(ls.st_mode)) {
        /* followed: the file the link names is replaced, the link stays */
        t = realpath(path, NULL);
        if (!t) {
            const int e = errno;
            if (e == ENOENT)
                return sss_fail(err, SSS_ERR_IO, "%s: is a symbolic link to a file that does not exist: not "
                                "written (links are followed only to an existing regular file)", path);
            if (e == ELOOP)
                return sss_fail(err, SSS_ERR_IO, "%s: is a loop of symbolic links: not written", path);
            return sss_fail(err, SSS_ERR_IO, "%s: cannot follow the symbolic link: %s", path, strerror(e));
        }
        if (stat(t, &st) != 0) {
            const int e = errno;
            free(t);
            return sss_fail(err, SSS_ERR_IO, "%s: cannot follow the symbolic link: %s", path, strerror(e));
        }
    } else {
        st = ls;
        t = dup_str(path);
    }
    if (!t) return sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory", path);
    if (exists && !S_ISREG(st.st_mode)) {
        free(t);
        return sss_fail(err, SSS_ERR_IO, "%s: is %s%s: not replaced (only a regular file, or a new one, is "
                        "written)", path, S_ISLNK(ls.st_mode) ? "a symbolic link to " : "", kind_of(st.st_mode));
    }
    for (size_t k = 0; exists && in && k < in->n; k++) {
        struct stat is;
        if (!in->path[k] || stat(in->path[k], &is) != 0) continue; /* an input gone is not this output */
        if (is.st_dev == st.st_dev && is.st_ino == st.st_ino) {
            free(t);
            return sss_fail(err, SSS_ERR_IO, "%s: is the same file as the input %s: not overwritten", path,
                            in->path[k]);
        }
    }
    if (target) *target = t;
    else free(t);
    return SSS_OK;
}

/* fsync of the directory holding path, so the rename itself is durable. */
static int sync_parent_dir(const char *path)
{
    const char *slash = strrchr(path, '/');
    char *dir;
    if (!slash) {
        dir = dup_str(".");
    } else {
        size_t n = slash == path ? 1 : (size_t)(slash - path);
        dir = malloc(n + 1);
        if (dir) { memcpy(dir, path, n); dir[n] = 0; }
    }
    if (!dir) { errno = ENOMEM; return -1; }
    int fd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    free(dir);
    if (fd < 0) return -1;
    int rc = fsync(fd);
    int e = errno;
    close(fd);
    /* Some file systems cannot sync directories; the rename has happened. */
    if (rc != 0 && (e == EINVAL || e == ENOTSUP || e == EROFS)) rc = 0;
    errno = e;
    return rc;
}

static void release(sss_atomic *a)
{
    free(a->path);
    free(a->target);
    free(a->tmp);
    a->path = a->target = a->tmp = NULL;
    a->fd = -1;
    a->in = NULL;
}

sss_result sss_atomic_begin(sss_atomic *a, const char *path, const sss_inputs *in, sss_error *err)
{
    memset(a, 0, sizeof *a);
    a->fd = -1;
    char *target = NULL;
    sss_result r = sss_output_check(path, in, &target, err);
    if (r != SSS_OK) return r;
    static const char suffix[] = ".tmp.XXXXXX";
    const size_t tl = strlen(target);
    a->path = dup_str(path);
    a->tmp = malloc(tl + sizeof suffix);
    a->target = target;
    a->in = in;
    if (!a->path || !a->tmp) {
        release(a);
        return sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory", path);
    }
    memcpy(a->tmp, target, tl);
    memcpy(a->tmp + tl, suffix, sizeof suffix);
    a->fd = mkstemp(a->tmp);
    if (a->fd < 0) {
        const int e = errno;
        release(a);
        return sss_fail(err, SSS_ERR_IO, "%s: cannot create temporary file: %s", path, strerror(e));
    }
    /* mkstemp creates 0600; keep the mode of the file being replaced, else 0644 */
    struct stat st;
    mode_t mode = 0644;
    if (stat(target, &st) == 0 && S_ISREG(st.st_mode)) mode = st.st_mode & 0777;
    (void)fchmod(a->fd, mode);
    return SSS_OK;
}

int sss_pwrite_all(int fd, const void *buf, size_t n, uint64_t off)
{
    const uint8_t *p = buf;
    while (n > 0) {
        size_t chunk = n > ((size_t)1 << 30) ? ((size_t)1 << 30) : n;
        ssize_t w = pwrite(fd, p, chunk, (off_t)off);
        if (w < 0) {
            if (errno == EINTR) continue;
            return -1;
        }
        if (w == 0) {
            errno = EIO;
            return -1;
        }
        p += w;
        n -= (size_t)w;
        off += (uint64_t)w;
    }
    return 0;
}

sss_result sss_atomic_write(sss_atomic *a, const void *buf, size_t len, sss_error *err)
{
    const uint8_t *p = buf;
    while (len > 0) {
        size_t chunk = len > ((size_t)1 << 30) ? ((size_t)1 << 30) : len;
        ssize_t w = write(a->fd, p, chunk);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) {
            const int e = w < 0 ? errno : EIO;
            return sss_fail(err, SSS_ERR_IO, "%s: write of temporary file failed: %s", a->path, strerror(e));
        }
        p += w;
        len -= (size_t)w;
    }
    return SSS_OK;
}

sss_result sss_atomic_commit(sss_atomic *a, sss_error *err)
{
    if (!a->tmp || a->fd < 0) {
        release(a);
        return sss_fail(err, SSS_ERR_ARG, "sss_atomic_commit: nothing begun");
    }
    const char *what = NULL;
    int e = 0;
    if (fsync(a->fd) != 0) what = "fsync", e = errno;
    if (close(a->fd) != 0 && !what) what = "close", e = errno;
    a->fd = -1;
    sss_result r = SSS_OK;
    if (what) {
        r = sss_fail(err, SSS_ERR_IO, "%s: %s of temporary file failed: %s", a->path, what, strerror(e));
    } else {
        /* the path again: it may have been replaced while the content was
         * made (a bake takes minutes) */
        char *t2 = NULL;
        r = sss_output_check(a->path, a->in, &t2, err);
        if (r == SSS_OK && strcmp(t2, a->target) != 0)
            r = sss_fail(err, SSS_ERR_IO, "%s: now names another file than when writing began: not replaced",
                         a->path);
        free(t2);
        if (r == SSS_OK && rename(a->tmp, a->target) != 0)
            r = sss_fail(err, SSS_ERR_IO, "%s: rename of temporary file failed: %s", a->path, strerror(errno));
    }
    if (r != SSS_OK) {
        unlink(a->tmp);
        release(a);
        return r;
    }
    if (sync_parent_dir(a->target) != 0)
        r = sss_fail(err, SSS_ERR_IO, "%s: written, but syncing its directory failed: %s", a->path, strerror(errno));
    release(a);
    return r;
}

void sss_atomic_abort(sss_atomic *a)
{
    if (!a) return;
    if (a->tmp && a->fd >= 0) close(a->fd);
    if (a->tmp) unlink(a->tmp);
    release(a);
}

sss_result sss_write_file(const char *path, const void *buf, size_t len, const sss_inputs *in, sss_error *err)
{
    sss_atomic a;
    sss_result r = sss_atomic_begin(&a, path, in, err);
    if (r != SSS_OK) return r;
    if ((r = sss_atomic_write(&a, buf, len, err)) != SSS_OK) {
        sss_atomic_abort(&a);
        return r;
    }
    return sss_atomic_commit(&a, err);
}
