/* fuzz_mesh.c: libFuzzer harness for the mesh importers (PLY ascii and
 * binary, OBJ, OFF, STL, glTF .gltf and .glb; docs/robustness.md). The first
 * input byte's low three bits pick the format (extension), its bit 3 asks
 * for the pose at t = 1 (sss_import_mesh_at: a glTF's skin moved by its
 * clip, docs/deformable.md §5), the rest is the file. The importer must
 * refuse it with a
 * message naming the file, or return a mesh whose indices are in range and
 * whose positions, normals and areas are finite. The importer reads paths
 * (OpenMesh does), so each input goes through a private temporary file. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "sss/import.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1) return 0;
    static const char *const ext[] = {".ply", ".obj", ".off", ".stl", ".gltf", ".glb", ".gltf", ".glb"};
    char path[64];
    snprintf(path, sizeof path, "/tmp/sss-fuzz-%ld%s", (long)getpid(), ext[data[0] & 7]);
    FILE *fp = fopen(path, "wb");
    if (!fp) return 0;
    if (size > 1 && fwrite(data + 1, 1, size - 1, fp) != size - 1) {
        fclose(fp);
        unlink(path);
        return 0;
    }
    fclose(fp);
    sss_mesh m;
    sss_import_report rep;
    sss_error err = {{0}};
    sss_result r = data[0] & 8 ? sss_import_mesh_at(path, 1.0, &m, &rep, &err) : sss_import_mesh(path, &m, &rep, &err);
    unlink(path);
    if (r != SSS_OK) {
        if (!strstr(err.msg, path)) abort(); /* the message names the file */
        return 0;
    }
    if (m.nv == 0 || m.nf == 0) abort();
    for (size_t i = 0; i < 3 * (size_t)m.nf; i++)
        if (m.tri[i] >= m.nv) abort();
    for (size_t i = 0; i < 3 * (size_t)m.nv; i++)
        if (!isfinite(m.pos[i]) || (m.nrm && !isfinite(m.nrm[i]))) abort();
    /* what a glTF carries besides positions comes with them, or not at all */
    if ((m.uv != NULL) != (rep.texcoords != 0) || (m.rgba != NULL) != (rep.colours != 0)) abort();
    for (size_t i = 0; m.area && i < m.nv; i++)
        if (!isfinite(m.area[i]) || m.area[i] < 0) abort();
    sss_mesh_free(&m);
    return 0;
}
