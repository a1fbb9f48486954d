/* import.c: mesh import (PLY, OBJ, OFF, STL, glTF) with validation and counted
 * repairs; see sss/import.h for the policy.
 *
 * The work is split in three:
 *
 *  1. Before anything large is allocated, the header is parsed from the first
 *     bytes of the file and the counts it declares are checked against the
 *     file's size (PLY, OFF, binary STL).
 *
 *  2. The file is read into memory and scanned in C. The scan rejects what
 *     OpenMesh's readers would silently misread (they turn a "nan" token into
 *     zeros, skip an unparsable OBJ vertex and so shift every later index,
 *     take a list length of 4e9 at face value, lose a binary PLY's data
 *     offset after a comment line, ...) with an error that names the element,
 *     and it canonicalises what they would misread although it is valid: the
 *     PLY header is rewritten (comments dropped, properties other than x y z
 *     renamed so the reader skips them by size, extra face properties
 *     compacted away), the OFF header is rewritten to plain "OFF" with the
 *     counts on their own line and trailing data on face lines blanked, and
 *     OBJ/STL lines the reader has no use for are turned into comments.
 *     The scan also predicts exactly what the reader must deliver, so a
 *     disagreement is caught instead of producing a wrong mesh.
 *
 *  3. OpenMesh parses the canonical bytes into a raw polygon soup
 *     (import_openmesh.cpp); the soup is checked (finite coordinates, indices
 *     in range), repaired (fan triangulation, degenerate faces dropped,
 *     unreferenced vertices removed) and turned into an sss_mesh.
 *
 * Steps 1 and 2 are one scanner per format (import_ply.c, import_off.c,
 * import_obj.c, import_stl.c, sharing import_scan.c); step 3 is repair.c
 * and orient.c. This file holds the format table and the pipeline.
 */
#define _POSIX_C_SOURCE 200809L

#include "input/import_internal.h"

#include <math.h>

/* The formats, by file extension (any case). Adding one is a scanner
 * file (import_internal.h) and one row here. */
static const struct {
    const char *ext;
    sss_result (*scan)(src *, expect *, sss_error *);
    /* the reader of the scanner's canonical bytes (OpenMesh or Assimp) */
    sss_om_status (*read)(const char *, size_t, sss_om_format, sss_om_soup *, char *, size_t);
} formats[] = {
    {"ply", sss_scan_ply, sss_om_read},
    {"obj", sss_scan_obj, sss_om_read},
    {"off", sss_scan_off, sss_om_read},
    {"stl", sss_scan_stl, sss_om_read},
    {"gltf", sss_scan_gltf, sss_ai_read},
    {"glb", sss_scan_gltf, sss_ai_read},
};
enum { NFORMATS = sizeof formats / sizeof formats[0] };

/* The row of path's extension (*ext: the extension with its dot, or ""),
 * or -1. */
static int format_of(const char *path, const char **ext)
{
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    const char *dot = strrchr(base, '.');
    *ext = dot ? dot : "";
    if (!dot) return -1;
    tok t = {(char *)(dot + 1), strlen(dot + 1)};
    for (int i = 0; i < NFORMATS; i++)
        if (tok_is_ci(t, formats[i].ext)) return i;
    return -1;
}

/* ".ply, .obj, .off, .stl, .gltf or .glb" from the table. */
static void formats_list(char *buf, size_t n)
{
    size_t k = 0;
    buf[0] = 0;
    for (int i = 0; i < NFORMATS && k < n; i++)
        k += (size_t)snprintf(buf + k, n - k, "%s.%s", i == 0 ? "" : i + 1 < NFORMATS ? ", " : " or ", formats[i].ext);
}

static sss_result import_mesh(const char *path, int pose, double t, sss_mesh *out, sss_import_report *rep,
                              sss_error *err);

sss_result sss_import_mesh(const char *path, sss_mesh *out, sss_import_report *rep, sss_error *err)
{
    return import_mesh(path, 0, 0.0, out, rep, err);
}

sss_result sss_import_mesh_at(const char *path, double t, sss_mesh *out, sss_import_report *rep, sss_error *err)
{
    if (!isfinite(t)) {
        if (out) memset(out, 0, sizeof *out);
        return sss_fail(err, SSS_ERR_ARG, "%s: time %g is not a finite number", path ? path : "import", t);
    }
    return import_mesh(path, 1, t, out, rep, err);
}

static sss_result import_mesh(const char *path, int pose, double t, sss_mesh *out, sss_import_report *rep,
                              sss_error *err)
{
    sss_import_report local;
    if (!rep) rep = &local;
    memset(rep, 0, sizeof *rep);
    if (out) memset(out, 0, sizeof *out);
    if (!path || !out) return sss_fail(err, SSS_ERR_ARG, "import: no path or no output mesh");

    const char *ext;
    int ff = format_of(path, &ext);
    if (ff < 0) {
        char known[96];
        formats_list(known, sizeof known);
        if (!*ext) return sss_fail(err, SSS_ERR_FORMAT, "%s: no file extension (expected %s)", path, known);
        return sss_fail(err, SSS_ERR_FORMAT, "%s: unknown extension '%s' (expected %s)", path, ext, known);
    }

    src s;
    expect ex;
    memset(&ex, 0, sizeof ex);
    ex.pose = pose;
    ex.pose_t = t;
    sss_result r = sss_src_open(&s, path, err);
    if (r == SSS_OK) r = formats[ff].scan(&s, &ex, err);
    if (s.f) { fclose(s.f); s.f = NULL; }

    sss_om_soup soup;
    memset(&soup, 0, sizeof soup);
    if (r == SSS_OK) {
        char msg[400];
        sss_om_status st = formats[ff].read(ex.om_data, ex.om_len, ex.fmt, &soup, msg, sizeof msg);
        if (st == SSS_OM_NO_MEMORY) r = sss_fail(err, SSS_ERR_NOMEM, "%s: %s", path, msg);
        else if (st != SSS_OM_OK) r = sss_fail(err, SSS_ERR_FORMAT, "%s: %s", path, msg);
    }
    /* The memory copy of the file (and a canonical one) is not needed any more. */
    free(s.mem);
    s.mem = NULL;
    free(ex.own);
    ex.own = NULL;

    if (r == SSS_OK) {
        /* The reader must deliver what the scan predicted. */
        if (ex.nv != ULLONG_MAX ? soup.nv != ex.nv : soup.nv > ex.nv_max)
            r = sss_fail(err, SSS_ERR_FORMAT, "%s: the reader delivered %llu vertices, the file has %llu", path,
                         (ull)soup.nv, ex.nv != ULLONG_MAX ? ex.nv : ex.nv_max);
        else if (ex.nf != ULLONG_MAX ? soup.nf != ex.nf : soup.nf > ex.nf_max)
            r = sss_fail(err, SSS_ERR_FORMAT, "%s: the reader delivered %llu faces, expected %llu", path, (ull)soup.nf,
                         ex.nf != ULLONG_MAX ? ex.nf : ex.nf_max);
    }
    if (r == SSS_OK && ex.uv && !soup.uv && soup.nv == ex.nv) {
        /* the scan's texture coordinates (PLY, OBJ), in the reader's vertex
         * order as the positions are; the repair carries them through */
        soup.uv = ex.uv;
        ex.uv = NULL;
    }
    if (r == SSS_OK) {
        /* STL: the reader merges equal corners and drops the triangles that
         * then use a vertex twice. */
        if (ex.nf == ULLONG_MAX) ex.repeated += ex.nf_max - soup.nf;
        r = sss_soup_to_mesh(path, &soup, &ex, out, rep, err);
        /* after the recentring: the range every stage computes in
         * (sss/mesh.h), before anything reaches Embree */
        if (r == SSS_OK) r = sss_mesh_check_range(out, 0.0, path, err);
        rep->animated = ex.animated;
        rep->clip_start = ex.clip_t0;
        rep->clip_end = ex.clip_t1;
    }
    sss_om_soup_free(&soup);
    free(ex.drop);
    free(ex.dpos);
    free(ex.uv);
    free(ex.own);
    sss_src_close(&s);
    if (r != SSS_OK) sss_mesh_free(out);
    return r;
}

uint64_t sss_import_repairs(const sss_import_report *rep)
{
    if (!rep) return 0;
    return rep->polygons_triangulated + rep->faces_too_small + rep->faces_repeated_index + rep->faces_zero_area +
           rep->vertices_unreferenced + rep->faces_duplicate + rep->faces_flipped + rep->open_faces_flipped +
           rep->recentred;
}

void sss_import_print_repairs(const sss_import_report *rep, const char *prefix, void *stream)
{
    if (!rep) return;
    FILE *f = stream ? (FILE *)stream : stderr;
    const char *sep = (prefix && *prefix) ? ": " : "";
    if (!prefix) prefix = "";
    struct { uint64_t n; const char *one, *many; } lines[] = {
        {rep->polygons_triangulated, "polygon with more than 3 vertices fan-triangulated",
         "polygons with more than 3 vertices fan-triangulated"},
        {rep->faces_too_small, "face with fewer than 3 vertices dropped", "faces with fewer than 3 vertices dropped"},
        {rep->faces_repeated_index, "face using a vertex more than once dropped",
         "faces using a vertex more than once dropped"},
        {rep->faces_zero_area, "zero-area triangle dropped", "zero-area triangles dropped"},
        {rep->vertices_unreferenced, "unreferenced vertex removed", "unreferenced vertices removed"},
        {rep->polygons_ear_clipped, "non-convex polygon ear-clipped in its plane instead (a fan would fold over)",
         "non-convex polygons ear-clipped in their plane instead (a fan would fold over)"},
        {rep->faces_duplicate, "triangle repeating an earlier one's vertices dropped",
         "triangles repeating an earlier one's vertices dropped"},
        {rep->faces_flipped, "triangle of a closed surface flipped to face outward consistently",
         "triangles of closed surfaces flipped to face outward consistently"},
        {rep->surfaces_inside_out, "closed surface was inside out as a whole", "closed surfaces were inside out as a whole"},
        {rep->open_faces_flipped, "triangle of an open surface flipped to agree with the majority of its surface",
         "triangles of open surfaces flipped to agree with the majority of their surface"},
    };
    for (size_t i = 0; i < sizeof lines / sizeof lines[0]; i++)
        if (lines[i].n)
            fprintf(f, "%s%srepaired: %llu %s\n", prefix, sep, (ull)lines[i].n, lines[i].n == 1 ? lines[i].one : lines[i].many);
    if (rep->recentred)
        fprintf(f, "%s%srepaired: mesh recentred: (%.17g, %.17g, %.17g) subtracted from every position, as its centre lies "
                "far from the origin for its size (float32 positions)\n", prefix, sep, rep->offset[0], rep->offset[1],
                rep->offset[2]);
}

void sss_import_print_warnings(const sss_import_report *rep, const char *prefix, void *stream)
{
    if (!rep) return;
    FILE *f = stream ? (FILE *)stream : stderr;
    const char *sep = (prefix && *prefix) ? ": " : "";
    if (!prefix) prefix = "";
    if (rep->polygons_unclipped)
        fprintf(f, "%s%swarning: %llu non-convex polygon%s could not be ear-clipped (self-intersecting, more than %d "
                "vertices, or past the import's ear-clipping budget) and %s fan-triangulated: some of %s triangles may overlap or face the wrong way\n", prefix, sep,
                (ull)rep->polygons_unclipped, rep->polygons_unclipped == 1 ? "" : "s", SSS_IMPORT_EAR_MAX,
                rep->polygons_unclipped == 1 ? "was" : "were", rep->polygons_unclipped == 1 ? "its" : "their");
    if (rep->unknown_statements)
        fprintf(f, "%s%swarning: %llu line%s with a statement OBJ does not have %s ignored (the first: '%s' on line "
                "%llu)\n", prefix, sep, (ull)rep->unknown_statements, rep->unknown_statements == 1 ? "" : "s",
                rep->unknown_statements == 1 ? "was" : "were", rep->first_unknown, (ull)rep->first_unknown_line);
    if (rep->orientation_conflicts)
        fprintf(f, "%s%swarning: %llu edge%s between triangles of opposite orientation could not be made consistent "
                "(a non-orientable surface such as a Moebius strip): normals there are unreliable\n", prefix, sep,
                (ull)rep->orientation_conflicts, rep->orientation_conflicts == 1 ? "" : "s");
    if (rep->primitives_skipped)
        fprintf(f, "%s%swarning: %llu glTF primitive%s of points or lines skipped (no surface to bake)\n", prefix, sep,
                (ull)rep->primitives_skipped, rep->primitives_skipped == 1 ? "" : "s");
}
