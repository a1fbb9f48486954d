/* fieldio.c: material fields on disk (sss/fieldio.h, docs/heterogeneous.md
 * §6). The file is read and written through sss/fileio.h (regular files
 * only, atomic replacement); OpenVDB parses and builds the bytes behind
 * the C++17 adapter vdb_io.cpp.
 */
#include "sss/fieldio.h"

#include <stdlib.h>
#include <string.h>

#include "input/vdb_io.h"
#include "sss/fileio.h"

sss_result sss_field_load(const char *path, const char *grid, sss_field *out, sss_error *err)
{
    memset(out, 0, sizeof *out);
    char *buf = NULL;
    size_t len = 0;
    sss_result r = sss_input_read_all(path, SSS_VDB_MAX_BYTES, &buf, &len, err);
    if (r != SSS_OK) return r;
    char msg[400] = "";
    sss_field f;
    memset(&f, 0, sizeof f);
    f.kind = SSS_FIELD_GRID;
    const int rc = sss_vdb_read(buf, len, grid, SSS_FIELD_GRID_MAX_NODES, &f.data, f.n, f.origin_mm, &f.voxel_mm,
                                msg, sizeof msg);
    free(buf);
    if (rc != 0) return sss_fail(err, SSS_ERR_ARG, "%s: %s", path, msg);
    sss_error e2 = {{0}};
    if (sss_field_check(&f, &e2) != SSS_OK) {
        sss_field_free(&f);
        return sss_fail(err, SSS_ERR_ARG, "%s: grid '%s': %s", path, grid, e2.msg);
    }
    *out = f;
    return SSS_OK;
}

sss_result sss_field_write_vdb(const char *path, const char *grid, const sss_field *f, sss_error *err)
{
    if (f->kind != SSS_FIELD_GRID || !f->data)
        return sss_fail(err, SSS_ERR_ARG, "%s: only a sampled (grid) field can be written as .vdb", path);
    char msg[400] = "", *buf = NULL;
    size_t len = 0;
    if (sss_vdb_write(f->data, f->n, f->origin_mm, f->voxel_mm, grid, &buf, &len, msg, sizeof msg) != 0)
        return sss_fail(err, SSS_ERR_ARG, "%s: %s", path, msg);
    sss_result r = sss_write_file(path, buf, len, NULL, err);
    free(buf);
    return r;
}
