/* sss/fileio.h: the one place that decides how the toolkit opens the files
 * it reads and replaces the files it writes (docs/robustness.md, "Paths";
 * docs/format.md §6–7). Every reader (the .sss reader, the mesh importers,
 * scene files, environment probes) opens through sss_input_open, and every
 * writer (the .sss writer, PNG and EXR images, exported meshes and probes)
 * writes through sss_atomic_*, which asks sss_output_check first.
 *
 * Reading. The file is opened with O_NONBLOCK, so that a FIFO, a device or
 * a socket given as an input cannot block the open; anything but a regular
 * file is refused after fstat, before a byte is read; then the descriptor
 * is made blocking again for the reads.
 *
 * Writing. A path may be written when
 *   - it does not exist, or names an existing regular file;
 *   - it is not the same file, by device and inode, as any of the inputs
 *     the caller names (a bake's mesh, a viewer's .sss file, ...);
 *   - and, for a symbolic link: the link is followed and the file it names
 *     is what is checked and replaced (atomically, in that file's
 *     directory), so the link stays a link; a link to nothing, a loop of
 *     links, or a link to anything but a regular file is refused.
 * Anything else that exists (a directory, a device node such as /dev/null,
 * a FIFO, a socket) is refused, never replaced. The new content goes to a
 * temporary file in the target's directory, is synced, the path is checked
 * again, and the temporary file is renamed over the target (then the
 * directory is synced): the target holds the old content or the complete
 * new one, never a partial one, and a failure leaves no temporary behind.
 *
 * Messages are one line naming the file ("out.png: is a directory: ...").
 */
#ifndef SSS_FILEIO_H
#define SSS_FILEIO_H

#include <stddef.h>
#include <stdint.h>
#include "sss/result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Files an output must not be: paths as given (symbolic links are followed
 * when they are compared). NULL, or n = 0: none. */
typedef struct sss_inputs {
    const char *const *path;
    size_t n;
} sss_inputs;

/* Opens path for reading (see the top of this file): *fd (O_CLOEXEC,
 * blocking) and *size in bytes. Refuses, naming the path, a path that
 * cannot be opened and anything but a regular file. */
sss_result sss_input_open(const char *path, int *fd, uint64_t *size, sss_error *err);

/* The whole file at path, opened as above, into a malloc'ed buffer with a
 * NUL after its last byte (*buf, *len; the caller frees). Refuses files of
 * more than max_bytes bytes (0: no limit) before allocating. */
sss_result sss_input_read_all(const char *path, uint64_t max_bytes, char **buf, size_t *len, sss_error *err);

/* Whether path may be written (see the top of this file): SSS_OK, or
 * SSS_ERR_IO with the reason. When target is non-NULL, *target receives the
 * path of the file that would be replaced (the path itself, or the file a
 * symbolic link names), malloc'ed; the caller frees it. */
sss_result sss_output_check(const char *path, const sss_inputs *in, char **target, sss_error *err);

/* An output being written: sss_atomic_begin checks the path and creates
 * the temporary file (fd), the caller writes its content to fd (or with
 * sss_atomic_write), then sss_atomic_commit makes it the file's content or
 * sss_atomic_abort throws it away. Several outputs may be begun before
 * any is committed, so that a tool writing several files writes none of
 * them when one fails. */
typedef struct sss_atomic {
    int fd;              /* the temporary file, open for writing; -1 when none */
    char *path;          /* as given, for messages and the second check */
    char *target;        /* the file replaced */
    char *tmp;           /* the temporary file's path */
    const sss_inputs *in;
} sss_atomic;

sss_result sss_atomic_begin(sss_atomic *a, const char *path, const sss_inputs *in, sss_error *err);
/* Writes all of buf to the temporary file (retrying short writes and EINTR). */
sss_result sss_atomic_write(sss_atomic *a, const void *buf, size_t len, sss_error *err);
/* fsync, close, the output check again, rename over the target, fsync of
 * the directory. On failure the temporary file is removed. Either way a
 * is released. */
sss_result sss_atomic_commit(sss_atomic *a, sss_error *err);
/* Closes and removes the temporary file and releases a; safe on a
 * released or zeroed sss_atomic. */
void sss_atomic_abort(sss_atomic *a);

/* begin, write len bytes of buf, commit. */
sss_result sss_write_file(const char *path, const void *buf, size_t len, const sss_inputs *in, sss_error *err);

/* pwrite of all n bytes at offset off; 0, or -1 with errno. For writers
 * that place their bytes themselves (the OpenEXR stream callbacks). */
int sss_pwrite_all(int fd, const void *buf, size_t n, uint64_t off);

#ifdef __cplusplus
}
#endif
#endif
