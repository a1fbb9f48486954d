/* renderer.c: OpenGL renderer for baked translucent meshes (sss/render.h):
 * creation of its parts (renderer.h) and the order of their work in a
 * frame: q from the direction set (scatter.c) or uploaded, then the passes
 * of the effects the file carries over q (effects/: the near terms of
 * OWNT), then the draw (draw.c).
 */
#include <epoxy/gl.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "effects/effects.h"
#include "renderer.h"
#include "shadow.h"

/* The mesh's geometry and the per-vertex q buffer. */
static void mesh_upload(sss_gpu_mesh *m)
{
    const sss_bake_file *f = m->f;
    glGenVertexArrays(1, &m->vao);
    glBindVertexArray(m->vao);
    glGenBuffers(1, &m->vbo_pos);
    glBindBuffer(GL_ARRAY_BUFFER, m->vbo_pos);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)m->nv * 3 * sizeof(float), f->mesh.pos, GL_STATIC_DRAW);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, NULL);
    glEnableVertexAttribArray(0);
    glGenBuffers(1, &m->vbo_nrm);
    glBindBuffer(GL_ARRAY_BUFFER, m->vbo_nrm);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)m->nv * 3 * sizeof(float), f->mesh.nrm, GL_STATIC_DRAW);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 0, NULL);
    glEnableVertexAttribArray(1);
    glGenBuffers(1, &m->ebo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, m->ebo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)m->nf * 3 * sizeof(uint32_t), f->mesh.tri, GL_STATIC_DRAW);
    glBindVertexArray(0);
    glGenBuffers(1, &m->qbuf);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, m->qbuf);
    glBufferData(GL_SHADER_STORAGE_BUFFER, (GLsizeiptr)m->nv * m->C * sizeof(float), NULL, GL_DYNAMIC_DRAW);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
}

/* The passes over q of the effects f carries (the pass table's rows of
 * light kind < 0), in table order. */
static sss_result passes_create(sss_renderer *r, sss_error *err)
{
    sss_effect_ctx c = {&r->mesh, 0, 0, 0};
    glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &c.max_block);
    for (unsigned i = 0; i < sss_pass_table_n; i++) {
        const sss_effect *e = &sss_pass_table[i];
        if (e->light_kind >= 0 || !sss_effect_present(e, r->mesh.f)) continue;
        sss_result res = e->create(&c, &r->pass[i], err);
        if (res != SSS_OK) return res;
        r->pass_on |= 1u << i;
    }
    return SSS_OK;
}

/* The state of the near terms' pass (OWNT), NULL when the file has none. */
static void *near_state(const sss_renderer *r)
{
    for (unsigned i = 0; i < sss_pass_table_n; i++)
        if ((r->pass_on >> i & 1) && !strcmp(sss_pass_table[i].section, "OWNT")) return r->pass[i];
    return NULL;
}

static sss_result renderer_create(const sss_bake_file *f, int vector, sss_renderer **out, sss_error *err)
{
    *out = NULL;
    if (epoxy_gl_version() < 43)
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "OpenGL 4.3 or newer is needed (this context has %d.%d)",
                        epoxy_gl_version() / 10, epoxy_gl_version() % 10);
    sss_renderer *r = calloc(1, sizeof *r);
    if (!r) return sss_fail(err, SSS_ERR_NOMEM, "renderer: out of memory");
    sss_gpu_mesh *m = &r->mesh;
    m->f = f;
    m->nv = f->mesh.nv;
    m->nf = f->mesh.nf;
    m->C = f->channels;
    m->radius = sss_mesh_bounding_sphere(&f->mesh, m->centre);

    sss_result res = vector ? sss_scatter_create(&r->scatter, m, err) : sss_scatter_create_scalar(&r->scatter, m, err);
    if (res == SSS_OK) res = sss_draw_create(&r->draw, err);
    if (res == SSS_OK) {
        mesh_upload(m);
        glGenQueries(3, r->queries);
        res = passes_create(r, err);
    }
    if (res != SSS_OK) {
        sss_renderer_destroy(r);
        return res;
    }
    if (glGetError() == GL_OUT_OF_MEMORY) {
        sss_renderer_destroy(r);
        return sss_fail(err, SSS_ERR_NOMEM, "renderer: the GPU is out of memory for %u directions x %u vertices",
                        f->dirs.n, f->mesh.nv);
    }
    *out = r;
    return SSS_OK;
}

sss_result sss_renderer_create(const sss_bake_file *f, sss_renderer **out, sss_error *err)
{
    return renderer_create(f, 1, out, err);
}

sss_result sss_renderer_create_scalar(const sss_bake_file *f, sss_renderer **out, sss_error *err)
{
    return renderer_create(f, 0, out, err);
}

int sss_renderer_vector(const sss_renderer *r) { return r->scatter.layout.vector; }

void sss_renderer_destroy(sss_renderer *r)
{
    if (!r) return;
    for (unsigned i = 0; i < sss_pass_table_n; i++)
        if ((r->pass_on >> i & 1) && sss_pass_table[i].destroy) sss_pass_table[i].destroy(r->pass[i]);
    sss_scatter_destroy(&r->scatter);
    sss_draw_destroy(&r->draw);
    GLuint bufs[4] = {r->mesh.vbo_pos, r->mesh.vbo_nrm, r->mesh.ebo, r->mesh.qbuf};
    glDeleteBuffers(4, bufs);
    if (r->mesh.vao) glDeleteVertexArrays(1, &r->mesh.vao);
    if (r->queries[0]) glDeleteQueries(3, r->queries);
    free(r);
}

/* The passes over q of the effects the file carries, for unit light l, in
 * table order; the near terms' timer is queries[2]. */
static void q_passes(sss_renderer *r, const double l[3], const sss_view_params *p)
{
    sss_effect_frame fr;
    memset(&fr, 0, sizeof fr);
    fr.light = l;
    fr.p = p;
    fr.query = r->queries[2];
    fr.r = r;
    for (unsigned i = 0; i < sss_pass_table_n; i++)
        if ((r->pass_on >> i & 1) && sss_pass_table[i].frame(r->pass[i], &fr)) r->have_times |= 4;
}

void sss_renderer_evaluate(sss_renderer *r, const sss_view_params *p)
{
    double l[3] = {p->light[0], p->light[1], p->light[2]};
    sss_normalize3(l);
    r->last_path = p->path;
    r->near_pending = 0;
    r->have_times &= ~4; /* near_ms: only when this frame runs the passes */
    if (p->path == SSS_EVAL_CPU) {
        sss_scatter_cpu(&r->scatter, &r->mesh, l, p->interp);
    } else {
        sss_scatter_gpu(&r->scatter, &r->mesh, l, p, r->queries[0]);
        r->have_times |= 1;
    }
    q_passes(r, l, p);
}

void sss_renderer_draw(sss_renderer *r, const sss_view_params *p, int width, int height)
{
    if (r->near_pending) {
        /* uploaded q: its near terms for this frame's light, once */
        double l[3] = {p->light[0], p->light[1], p->light[2]};
        sss_normalize3(l);
        q_passes(r, l, p);
        r->near_pending = 0;
    }
    sss_draw_frame(&r->draw, &r->mesh, p, width, height, r->queries[1]);
    r->have_times |= 2;
}

void sss_renderer_read_q(sss_renderer *r, float *out)
{
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, r->mesh.qbuf);
    glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)r->mesh.nv * r->mesh.C * sizeof(float), out);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
}

void sss_renderer_read_near_visibility(sss_renderer *r, uint8_t *lit)
{
    const void *near = near_state(r);
    if (!near) {
        memset(lit, 1, r->mesh.nv); /* no own term: nothing was tested */
        return;
    }
    sss_near_read_visibility(near, r->mesh.nv, lit);
}

int sss_renderer_has_near_terms(const sss_renderer *r)
{
    for (unsigned i = 0; i < sss_pass_table_n; i++)
        if ((r->pass_on >> i & 1) && !strcmp(sss_pass_table[i].section, "OWNT")) return 1;
    return 0;
}

sss_frame_times sss_renderer_times(const sss_renderer *r)
{
    sss_frame_times t = {0, 0, 0};
    GLuint64 ns = 0;
    if (r->last_path == SSS_EVAL_CPU) t.scatter_ms = r->scatter.cpu_ms;
    else if (r->have_times & 1) {
        glGetQueryObjectui64v(r->queries[0], GL_QUERY_RESULT, &ns);
        t.scatter_ms = 1e-6 * (double)ns;
    }
    if (r->have_times & 2) {
        glGetQueryObjectui64v(r->queries[1], GL_QUERY_RESULT, &ns);
        t.draw_ms = 1e-6 * (double)ns;
    }
    if (r->have_times & 4) {
        glGetQueryObjectui64v(r->queries[2], GL_QUERY_RESULT, &ns);
        t.near_ms = 1e-6 * (double)ns;
    }
    return t;
}

unsigned sss_renderer_q_buffer(const sss_renderer *r) { return r->mesh.qbuf; }

const char *sss_renderer_scheme(const sss_renderer *r, const sss_view_params *p)
{
    if (p->path == SSS_EVAL_CPU) return "cpu";
    if (!r->scatter.layout.sh_bytes) return "rows";
    return sss_scatter_storage(&r->scatter, p) ? "storage tables" : "uniform tables";
}

double sss_renderer_bytes_per_vertex(const sss_renderer *r) { return sss_file_integral_bytes_per_vertex(r->mesh.f); }

void sss_storage_describe(const sss_bake_file *f, char *buf, size_t n)
{
    if (!n) return;
    const char *q = sss_quant_name(f->quant);
    const sss_shcode *s = &f->sh;
    if (f->quant == SSS_QUANT_SH) {
        snprintf(buf, n, "%s: SH %u %s", q, s->order, sss_shq_name(s->kind));
    } else if (f->quant == SSS_QUANT_REFS) {
        double pct = f->mesh.nv ? 100.0 * f->ref.nref / f->mesh.nv : 0.0;
        if (s->ncoef)
            snprintf(buf, n, "%s %.1f%% + SH %u %s, %u-bit weights", q, pct, s->order, sss_shq_name(s->kind),
                     f->ref.wbits);
        else
            snprintf(buf, n, "%s %.1f%%, %u-bit weights", q, pct, f->ref.wbits);
    } else {
        /* the vector integrals Q are what is drawn (section QVEC) */
        snprintf(buf, n, "%s%s", q, f->qvec ? " + vector Q (drawn)" : "");
    }
}

void sss_renderer_update_geometry(sss_renderer *r)
{
    const sss_gpu_mesh *m = &r->mesh;
    glBindBuffer(GL_ARRAY_BUFFER, m->vbo_pos);
    glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)m->nv * 3 * sizeof(float), m->f->mesh.pos);
    glBindBuffer(GL_ARRAY_BUFFER, m->vbo_nrm);
    glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)m->nv * 3 * sizeof(float), m->f->mesh.nrm);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    /* the surface terms' shadow map was rendered from the old shape */
    if (r->draw.shadow) sss_shadow_invalidate(r->draw.shadow);
}

void sss_renderer_upload_q(sss_renderer *r, const float *q)
{
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, r->mesh.qbuf);
    glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)r->mesh.nv * r->mesh.C * sizeof(float), q);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    /* the light is not known here: the next draw adds the near terms */
    r->near_pending = r->pass_on != 0;
    r->have_times &= ~4;
}
