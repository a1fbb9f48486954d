/* bake.c: the precompute pipeline (Hao–Varshney 2004 §3): neighbourhoods,
 * visibility and transfer, integrals, quantisation, assembled into an
 * sss_bake_file. Each phase is timed for the benchmarks.
 */
#include "sss/bake.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "bake/bake_tree.h"
#include "effects/effect.h"
#include "kernels/progress.h"
#include "kernels/thickness.h"
#include "sss/compress.h"
#include "sss/lloyd.h"
#include "sss/memory.h"
#include "sss/nbhd.h"
#include "sss/nearterms.h"
#include "sss/transfer.h"
#include "sss/visibility.h"

/* cos 30°: the bend along a long edge that the linear irradiance between
 * its ends cannot follow (the resolution check below) */
#define SSS_COARSE_BEND_COS 0.8660254037844387

static sss_result copy_mesh(const sss_mesh *src, sss_mesh *dst, sss_error *err)
{
    const sss_mesh geom = {.nv = src->nv, .nf = src->nf, .pos = src->pos, .tri = src->tri}; /* normals recomputed below */
    sss_result r = sss_mesh_copy(&geom, dst, err);
    if (r != SSS_OK) return r;
    r = sss_mesh_compute_normals_areas(dst, "mesh", err);
    if (r != SSS_OK) sss_mesh_free(dst);
    return r;
}

/* Bake parameters as JSON, for provenance. Only inputs go here (no thread
 * count, no timings), so the file's bytes depend on the inputs alone. The
 * import offset and the compression settings, when there are any, are
 * added through cJSON, whose number format the files made so far carry. */
static char *params_json(const char *mesh_name, const sss_material *m, const sss_bake_options *o,
                         uint32_t channels, const double *radius, double search, const sss_bake_stats *st)
{
    char buf[2048];
    const char *nm = mesh_name ? mesh_name : "";
    char esc[512];
    size_t k = 0;
    for (const char *p = nm; *p && k + 7 < sizeof esc; p++) {
        unsigned char ch = (unsigned char)*p;
        if (ch == '"' || ch == '\\') { esc[k++] = '\\'; esc[k++] = (char)ch; }
        else if (ch < 0x20) k += (size_t)snprintf(esc + k, sizeof esc - k, "\\u%04x", ch);
        else esc[k++] = (char)ch;
    }
    esc[k] = 0;
    /* format 1.8, section PHAS: the material's phase (an isotropic bake's text is unchanged) */
    char phase[40] = "";
    if (m->g != 0.0) snprintf(phase, sizeof phase, ",\"g\":%.17g", m->g);
    snprintf(buf, sizeof buf,
             "{\"generator\":\"sss-bake 0.1.0\",\"format\":\"%d.%d\",\"mesh\":\"%s\","
             "\"material\":{\"name\":\"%s\",\"sigma_a\":[%.17g,%.17g,%.17g],\"sigmap_s\":[%.17g,%.17g,%.17g],\"eta\":%.17g%s},"
             "\"mm_per_unit\":%.17g,\"dirs\":%u,\"direction_set\":\"spherical-fibonacci\",\"eps\":%.17g,"
             "\"channels\":%u,\"quant\":\"%s\",\"radius_mm\":[%.9g,%.9g,%.9g],\"search_radius_mm\":%.9g,"
             "\"normalisation\":\"q = sum F_t(eta,n_i.w) (1/pi) R_d(r) max(0,n_i.w) V dA; self term (1/pi) disk integral\","
             "\"visibility\":\"embree occlusion rays, origin offset 1e-5 of bbox diagonal along the normal\"}",
             SSS_FORMAT_MAJOR, SSS_FORMAT_MINOR_PLAIN, esc, m->name, m->sigma_a[0], m->sigma_a[1], m->sigma_a[2],
             m->sigmap_s[0], m->sigmap_s[1], m->sigmap_s[2], m->eta, phase, o->mm_per_unit, o->n_dirs, o->eps, channels,
             o->quant == SSS_QUANT_LLOYD8 ? "lloyd8" : "float", radius[0], radius[1], radius[2], search);
    if (o->gather == SSS_GATHER_TREE) { /* docs/benchmarks.md, "Bake at scale": which gather made q (the direct bake's text is unchanged) */
        const size_t L = strlen(buf);
        if (L > 0 && L + 64 < sizeof buf)
            snprintf(buf + L - 1, sizeof buf - (L - 1), ",\"gather\":\"tree\",\"theta\":%.17g}", o->theta);
    }
    if (o->near_terms && !(o->near_radius_mm > 0.0)) { /* format 1.3: what the rows hold (docs/format.md §5.14) */
        const size_t L = strlen(buf);
        if (L > 0 && L + 160 < sizeof buf)
            snprintf(buf + L - 1, sizeof buf - (L - 1), ",\"own_term\":\"runtime: rows hold q minus the sum over the "
                     "vertex and its mesh rings of w F_t(eta,n_i.w) max(0,n_i.w) V(x_i,w)\",\"own_rings\":%u}",
                     o->near_rings);
    } else if (o->near_terms) { /* format 1.5: the near terms by radius (docs/format.md §5.17) */
        /* a radius from the material: which fraction of R_d,total it holds */
        char frac[120] = "";
        if (o->near_fraction > 0.0)
            snprintf(frac, sizeof frac, ",\"near_fraction\":%.9g,\"near_fraction_held\":%.9g%s", o->near_fraction,
                     st->near_fraction_held, st->near_capped ? ",\"near_capped\":true" : "");
        const size_t L = strlen(buf);
        if (L > 0 && L + 330 < sizeof buf)
            snprintf(buf + L - 1, sizeof buf - (L - 1), ",\"own_term\":\"runtime: rows hold q minus the sum over the "
                     "vertices within near_radius_mm of w F_t(eta,n_i.w) max(0,n_i.w) V(x_i,w)\",\"near_radius_mm\":%.9g%s}",
                     o->near_radius_mm, frac);
    }
    if (o->weights == SSS_WEIGHTS_HAT) { /* format 1.5 (docs/format.md §5.16) */
        const size_t L = strlen(buf);
        if (L > 0 && L + 120 < sizeof buf)
            snprintf(buf + L - 1, sizeof buf - (L - 1), ",\"weights\":\"hat: (1/pi) integral of phi_i R_d over the "
                     "one-ring of x_i\"}");
    }
    if (o->vector) { /* format 1.7 (docs/format.md §5.19) */
        const size_t L = strlen(buf);
        if (L > 0 && L + 120 < sizeof buf)
            snprintf(buf + L - 1, sizeof buf - (L - 1), ",\"vector\":\"Q = sum F_t(eta,n_i.w) (1/pi) R_d(r) mu_i n_i V "
                     "dA; q = Q.w\"}");
    }
    if (!o->import_offset && !o->compress) {
        char *s = malloc(strlen(buf) + 1);
        if (s) strcpy(s, buf);
        return s;
    }
    cJSON *pj = cJSON_Parse(buf);
    if (!pj) return NULL;
    if (o->import_offset) /* GEOM holds the recentred positions (docs/robustness.md B6) */
        cJSON_AddItemToObject(pj, "import_offset", cJSON_CreateDoubleArray(o->import_offset, 3));
    if (o->compress) sss_compress_opts_to_json(o->compress, pj);
    char *s = cJSON_PrintUnformatted(pj);
    cJSON_Delete(pj);
    return s; /* cJSON allocates with malloc: sss_file_free frees it */
}

sss_result sss_bake(const sss_mesh *mesh_in, const char *mesh_name, const sss_material *mat,
                    const sss_bake_options *opt_in, sss_bake_file *out, sss_bake_stats *st_out, sss_error *err)
{
    memset(out, 0, sizeof *out);
    sss_bake_stats st;
    memset(&st, 0, sizeof st);
    sss_bake_options o = *opt_in;
    if (o.mm_per_unit == 0) o.mm_per_unit = 1.0;
    if (o.n_dirs == 0) o.n_dirs = 200;
    if (o.eps == 0) o.eps = 1e-3;
    if (!(o.mm_per_unit >= SSS_MM_PER_UNIT_MIN && o.mm_per_unit <= SSS_MM_PER_UNIT_MAX))
        return sss_fail(err, SSS_ERR_ARG, "--mm-per-unit %g must be a number in [%g, %g]", o.mm_per_unit,
                        SSS_MM_PER_UNIT_MIN, SSS_MM_PER_UNIT_MAX);
    if (!(o.eps > 0 && o.eps < 1)) return sss_fail(err, SSS_ERR_ARG, "eps %g must be in (0, 1)", o.eps);
    sss_result r0;
    if ((o.near_terms && o.near_terms != SSS_NEAR_TERMS_RUNTIME) || o.near_rings > SSS_NEAR_RINGS_MAX)
        return sss_fail(err, SSS_ERR_ARG, "own term %u with %u rings: rings must be 0 ... %u", o.near_terms, o.near_rings,
                        SSS_NEAR_RINGS_MAX);
    if (o.near_fraction != 0.0) { /* the radius from the material (docs/accuracy.md, "Near terms sized by the material") */
        if (!(o.near_fraction > 0.0 && o.near_fraction < 1.0) || !o.near_terms || o.near_radius_mm != 0.0)
            return sss_fail(err, SSS_ERR_ARG, "near-terms fraction %g: in (0, 1), with the near terms at run time and "
                            "no radius of its own", o.near_fraction);
        r0 = sss_material_validate(mat, err);
        if (r0 != SSS_OK) return r0;
        o.near_radius_mm = sss_near_radius_material(mat, sss_material_channels(mat), o.near_fraction);
    }
    if (!(o.near_radius_mm >= 0.0) || !isfinite(o.near_radius_mm) || (o.near_radius_mm > 0.0 && !o.near_terms))
        return sss_fail(err, SSS_ERR_ARG, "near-terms radius %g mm: a finite number >= 0, with the near terms at run time",
                        o.near_radius_mm);
    if (o.weights != SSS_WEIGHTS_POINT && o.weights != SSS_WEIGHTS_HAT)
        return sss_fail(err, SSS_ERR_ARG, "weight rule %u: 0 (point) or 1 (hat)", o.weights);
    if (o.n_dirs > 100000) return sss_fail(err, SSS_ERR_ARG, "--dirs %u out of range [1, 100000]", o.n_dirs);
    if (o.vector && (o.compress || o.nranks > 1)) /* Q is stored as float beside q's rows (docs/format.md §5.19) */
        return sss_fail(err, SSS_ERR_ARG, "the vector integrals Q are stored as float next to float or lloyd8 rows: "
                        "not with compression%s", o.nranks > 1 ? " nor under MPI" : "");
    if (o.compress && o.quant != SSS_QUANT_FLOAT)
        return sss_fail(err, SSS_ERR_ARG, "compression takes the float integrals: quant must be float");
#ifdef _OPENMP
    if (o.threads > 0) omp_set_num_threads(o.threads);
#endif
    sss_progress_enable(o.progress, o.progress_log);
    sss_result r = sss_material_validate(mat, err);
    if (r != SSS_OK) return r;

    const uint32_t C = sss_material_channels(mat);
    sss_dipole dip[SSS_MAX_CHANNELS];
    for (uint32_t c = 0; c < C; c++) sss_dipole_init(&dip[c], mat->sigma_a[c], mat->sigmap_s[c], mat->eta);

    sss_weights nb = {0}, hat = {0};
    float *G = NULL;
    r = copy_mesh(mesh_in, &out->mesh, err);
    if (r != SSS_OK) goto fail;
    /* the geometry's range in mm (sss/mesh.h): Embree, FLANN and the tree
     * gather compute in float */
    r = sss_mesh_check_range(&out->mesh, o.mm_per_unit, "mesh", err);
    if (r != SSS_OK) goto fail;
    const sss_mesh *mesh = &out->mesh;
    r = sss_dirset_fibonacci(&out->dirs, o.n_dirs, err);
    if (r != SSS_OK) goto fail;
    /* a file that stores its directions in float32 (DIRC) gets rows baked
     * at those directions, so the exact evaluator reproduces them */
    if (o.compress && o.compress->dirs_f32) sss_dirset_round_f32(&out->dirs);
    out->material = *mat;
    out->mm_per_unit = o.mm_per_unit;
    out->channels = C;
    out->quant = o.quant;

    /* Neighbourhood radius per channel: the disk that holds 1−ε of the total
     * diffuse reflectance, clamped to the object's size (α′ → 1). */
    st.search_radius_mm = sss_nbhd_radii(mesh, o.mm_per_unit, dip, C, o.eps, st.radius_mm);
    /* a radius from the material: within the neighbourhood, and shrunk to
     * SSS_NEAR_ENTRIES_MAX entries per vertex on an object small against
     * its range */
    if (o.near_fraction > 0.0)
        o.near_radius_mm = sss_near_radius_bake(mesh, o.mm_per_unit, mat, C, o.near_fraction, st.search_radius_mm,
                                                &st.near_capped, &st.near_fraction_held);
    /* Resolution check (docs/robustness.md B3): the smoothest profile has
     * scale 1/σtr of the channel with the smallest σtr (a vanishing σa means
     * an unbounded range: the radius stands in for it). With point weights
     * an edge longer than twice that puts area where R_d has decayed but
     * weighs it with R_d at the vertex. The hat-function weights integrate
     * R_d over such triangles correctly (docs/physics.md §9); what a long
     * edge still cannot carry is a bend: the irradiance is linear between
     * the vertices, so an edge longer than twice the range whose end normals
     * differ by more than 30° misplaces light by more than the scattering
     * averages. Counted, not refused: the user decides to resample. */
    {
        double range = 0.0;
        for (uint32_t c = 0; c < C; c++) {
            double rc = dip[c].sigma_tr > 0.0 ? 1.0 / dip[c].sigma_tr : st.radius_mm[c];
            if (rc > range) range = rc;
        }
        st.range_mm = range;
        const double lim = 2.0 * range / o.mm_per_unit; /* in mesh units */
        uint8_t *coarse = calloc(mesh->nv ? mesh->nv : 1, 1);
        double longest = 0.0;
        for (uint32_t t = 0; t < mesh->nf && coarse; t++)
            for (int k = 0; k < 3; k++) {
                const uint32_t a = mesh->tri[3 * (size_t)t + k], b = mesh->tri[3 * (size_t)t + (k + 1) % 3];
                double d2 = 0.0;
                for (int x = 0; x < 3; x++) {
                    double dx = (double)mesh->pos[3 * (size_t)a + x] - mesh->pos[3 * (size_t)b + x];
                    d2 += dx * dx;
                }
                const double len = sqrt(d2);
                if (len > longest) longest = len;
                if (!(len > lim)) continue;
                if (o.weights == SSS_WEIGHTS_HAT) {
                    const float *na = mesh->nrm + 3 * (size_t)a, *nb = mesh->nrm + 3 * (size_t)b;
                    if (na[0] * nb[0] + na[1] * nb[1] + na[2] * nb[2] >= SSS_COARSE_BEND_COS) continue;
                }
                coarse[a] = coarse[b] = 1;
            }
        for (uint32_t v = 0; v < mesh->nv && coarse; v++) st.coarse_vertices += coarse[v];
        st.longest_edge_mm = longest * o.mm_per_unit;
        free(coarse);
    }
    /* Thin parts (docs/robustness.md B8): where the object is thinner than
     * the range 1/σtr, the semi-infinite dipole counts the light gathered
     * through the part twice (a 4 mm slab with σa = 0 gives 1.7x the
     * incident light). The model stays (Hao–Varshney 2004 §3.1); the count
     * makes the tool warn. */
    st.thin_limit_mm = st.range_mm;
    r = sss_thin_count(mesh, st.range_mm / o.mm_per_unit, o.cancel, &st.thin_vertices, &st.thinnest_mm, err);
    if (r != SSS_OK) goto fail;
    st.thinnest_mm *= o.mm_per_unit;

    /* Say so before starting when the bake cannot fit in memory: the
     * transfer table G and the integrals are sized by the input; the
     * neighbourhood rows are counted before they are allocated. */
    uint64_t avail = sss_memory_available(o.memory_limit);
    uint64_t fixed = (uint64_t)mesh->nv * o.n_dirs * (4u + 4u * C + (o.quant == SSS_QUANT_LLOYD8 ? C : 0u) +
                                                      (o.vector ? 4u + 16u * C : 0u)); /* Q, one source and one component plane */
    const size_t nq = (size_t)o.n_dirs * mesh->nv * C;
    double t;
    st.gather = o.gather = sss_bake_choose_gather(&o);
    st.theta = o.theta = o.theta > 0 ? o.theta : SSS_GATHER_THETA_DEFAULT;
    /* The hat-function weights (docs/physics.md §9): the corrections to
     * the point weights, which the gathers below use as they are. Under MPI
     * the tree gather's rank 0 alone applies them (and the near terms need
     * them there); the direct gather sums every row on every rank. */
    const int hat_here = o.weights == SSS_WEIGHTS_HAT &&
                         (o.nranks <= 1 || o.rank == 0 || st.gather != SSS_GATHER_TREE);
    if (hat_here) {
        t = sss_now();
        sss_progress_begin("hat weights", 1);
        r = sss_hat_corrections(mesh, o.mm_per_unit, dip, C, st.search_radius_mm, NULL, 0, o.cancel, &hat, err);
        if (r == SSS_OK) sss_progress_tick(1);
        sss_progress_end();
        if (r != SSS_OK) goto fail;
        st.t_hat = sss_now() - t;
        st.hat_entries = hat.start[hat.nrows];
        fixed += st.hat_entries * (4u + 4u * C);
    }
    out->weights = o.weights;
    if (st.gather == SSS_GATHER_TREE) {
        r = sss_bake_tree(mesh, mat, &o, dip, C, avail > st.hat_entries * (4u + 4u * C) ? avail - st.hat_entries * (4u + 4u * C) : avail,
                          hat_here ? &hat : NULL, out, &st, err);
        if (r != SSS_OK) goto fail;
        goto quantise;
    }
    if (avail && fixed > avail) {
        r = sss_fail(err, SSS_ERR_NOMEM, "the bake needs at least %.2f GiB for %u vertices x %u directions but %.2f GiB "
                     "is available (estimate before starting; SSS_MEMORY_LIMIT_MB lowers the limit): use fewer --dirs", fixed / 1073741824.0, mesh->nv, o.n_dirs, avail / 1073741824.0);
        goto fail;
    }
    t = sss_now();
    sss_progress_begin("neighbourhoods", 2 * (uint64_t)mesh->nv); /* count pass + fill pass */
    r = sss_nbhd_build(mesh, o.mm_per_unit, dip, C, st.search_radius_mm, NULL, 0, avail ? (avail - fixed) / 10 * 9 : 0,
                       o.cancel, &nb, err);
    sss_progress_end();
    if (r != SSS_OK) goto fail;
    st.t_neighbourhoods = sss_now() - t;
    st.neighbours_total = nb.start[nb.nrows];
    st.neighbours_mean = (double)st.neighbours_total / (double)nb.nrows;
    for (uint32_t v = 0; v < nb.nrows; v++) {
        uint32_t k = (uint32_t)(nb.start[v + 1] - nb.start[v]);
        if (k > st.neighbours_max) st.neighbours_max = k;
    }

    t = sss_now();
    G = malloc((size_t)mesh->nv * o.n_dirs * sizeof(float) + 1);
    if (!G) { r = sss_fail(err, SSS_ERR_NOMEM, "out of memory for %u x %u transfer values", mesh->nv, o.n_dirs); goto fail; }
    r = sss_bake_visibility(mesh, mat->eta, out->dirs.dir, o.n_dirs, 0, mesh->nv, o.cancel, G, &st, err);
    if (r != SSS_OK) goto fail;
    st.t_visibility = sss_now() - t;

    t = sss_now();
    out->q = malloc(nq * sizeof(float) + 1);
    if (!out->q) { r = sss_fail(err, SSS_ERR_NOMEM, "out of memory for %zu integrals", nq); goto fail; }
    sss_progress_begin("integrals", nb.start[nb.nrows]); /* ticks neighbours: the work of a row */
    sss_integrate_hat(&nb, hat_here ? &hat : NULL, G, o.n_dirs, out->q);
    sss_progress_end();
    if (o.vector) { /* Q: three signed sums of the same rows (Hao–Varshney 2004 §3.1) */
        const double tv = sss_now();
        r = sss_bake_vector_direct(mesh, &out->dirs, &nb, hat_here ? &hat : NULL, G, &out->qvec, err);
        if (r != SSS_OK) goto fail;
        st.t_vector = sss_now() - tv;
    }
    st.t_integrals = sss_now() - t;
    free(G);
    G = NULL;
    if (st.t_integrals > 0) st.gather_gflops = 2.0 * (double)st.neighbours_total * o.n_dirs * C / st.t_integrals * 1e-9;
    st.predicted_peak_bytes = fixed + st.neighbours_total * (4u + 4u * C);
    sss_weights_free(&nb);
    if (sss_cancelled(o.cancel)) { r = sss_fail(err, SSS_ERR_INTERRUPTED, "interrupted during integrals"); goto fail; }

quantise:
    if (o.nranks > 1 && o.rank != 0) { /* under MPI only rank 0 has q and writes the file */
        if (st_out) *st_out = st;
        return SSS_OK;
    }
    if (o.near_terms) {
        t = sss_now();
        r = sss_near_terms_split_vector(mesh, mat, &o, C, &out->dirs, o.weights == SSS_WEIGHTS_HAT ? &hat : NULL,
                                        out->q, out->qvec, &st.rays, &st.near_entries, err);
        if (r != SSS_OK) goto fail;
        out->near_terms = SSS_NEAR_TERMS_RUNTIME;
        out->near_rings = o.near_radius_mm > 0.0 ? 0 : o.near_rings;
        out->near_radius_mm = o.near_radius_mm;
        st.t_visibility += sss_now() - t;
    }

    if (o.quant == SSS_QUANT_LLOYD8) {
        t = sss_now();
        out->levels = malloc(256 * C * sizeof(float));
        out->qidx = malloc(nq + 1);
        if (!out->levels || !out->qidx) { r = sss_fail(err, SSS_ERR_NOMEM, "out of memory for %zu indices", nq); goto fail; }
        double S = 0, N = 0;
        for (uint32_t c = 0; c < C; c++) {
            double s, n;
            r = sss_lloyd8(out->q + c, (uint64_t)o.n_dirs * mesh->nv, C, out->levels + 256 * c, out->qidx + c, &s, &n, err);
            if (r != SSS_OK) goto fail;
            st.lloyd_snr_db[c] = n > 0 ? 10.0 * log10(s / n) : INFINITY;
            S += s;
            N += n;
        }
        st.lloyd_snr_db_all = N > 0 ? 10.0 * log10(S / N) : INFINITY;
        free(out->q);
        out->q = NULL;
        st.t_quantise = sss_now() - t;
    }
    if (o.compress) {
        if (sss_cancelled(o.cancel)) { r = sss_fail(err, SSS_ERR_INTERRUPTED, "interrupted before compression"); goto fail; }
        t = sss_now();
        sss_bake_file cf;
        r = sss_compress(out, o.compress, &cf, err);
        if (r != SSS_OK) goto fail;
        sss_file_free(out);
        *out = cf;
        st.t_compress = sss_now() - t;
    }
    sss_weights_free(&hat);
    out->eps = o.eps;
    free(out->params_json);
    out->params_json = params_json(mesh_name, mat, &o, C, st.radius_mm, st.search_radius_mm, &st);
    if (!out->params_json) { r = sss_fail(err, SSS_ERR_NOMEM, "out of memory"); goto fail; }
    if (st_out) *st_out = st;
    return SSS_OK;

fail:
    free(G);
    sss_weights_free(&nb);
    sss_weights_free(&hat);
    sss_file_free(out);
    return r;
}
