/* font.c: the overlay font and its GL text renderer (font.h).
 *
 * The glyphs below were drawn by hand for this project, one 5×8 cell per
 * character: '#' is a lit pixel, '.' a dark one. They are laid out as in
 * the texture atlas (16 characters per band, 6 bands, bands top to bottom),
 * so what is seen here is what gets uploaded. Row 7 is only used by
 * descenders (g j p q y , _); lowercase letters with descenders sit one row
 * higher so that they fit into the cell.
 */
#include <epoxy/gl.h>

#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "font.h"
#include "sss/render.h"
#include "view_glsl.h" /* runtime/shaders/text.{vert,frag}.glsl, embedded at build time */

#define BANDS 6
#define PER_BAND 16
#define CELL_W SSS_FONT_ADVANCE
#define CELL_H SSS_FONT_GLYPH_H
#define ATLAS_W (PER_BAND * CELL_W)
#define ATLAS_H (BANDS * CELL_H)
/* Cell 95, the one after '~', is kept fully lit: boxes sample it, so text
 * and boxes share one shader, one texture and one draw call. */
#define SOLID_CELL 95

static const char *const font_art[BANDS * CELL_H] = {
    /* ' '   '!'   '"'   '#'   '$'   '%'   '&'   '''   '('   ')'   '*'   '+'   ','   '-'   '.'   '/'   */
    "..... ..#.. .#.#. .#.#. ..#.. ##... .##.. ..#.. ...#. .#... ..... ..... ..... ..... ..... .....",
    "..... ..#.. .#.#. .#.#. .#### ##..# #..#. ..#.. ..#.. ..#.. ..#.. ..#.. ..... ..... ..... ....#",
    "..... ..#.. .#.#. ##### #.#.. ...#. #.#.. .#... .#... ...#. #.#.# ..#.. ..... ..... ..... ...#.",
    "..... ..#.. ..... .#.#. .###. ..#.. .#... ..... .#... ...#. .###. ##### ..... ##### ..... ..#..",
    "..... ..#.. ..... ##### ..#.# .#... #.#.# ..... .#... ...#. #.#.# ..#.. ..... ..... ..... .#...",
    "..... ..... ..... .#.#. ####. #..## #..#. ..... ..#.. ..#.. ..#.. ..#.. .##.. ..... .##.. #....",
    "..... ..#.. ..... .#.#. ..#.. ...## .##.# ..... ...#. .#... ..... ..... ..#.. ..... .##.. .....",
    "..... ..... ..... ..... ..... ..... ..... ..... ..... ..... ..... ..... .#... ..... ..... .....",
    /* '0'   '1'   '2'   '3'   '4'   '5'   '6'   '7'   '8'   '9'   ':'   ';'   '<'   '='   '>'   '?'   */
    ".###. ..#.. .###. ##### ...#. ##### ..##. ##### .###. .###. ..... ..... ...#. ..... .#... .###.",
    "#...# .##.. #...# ...#. ..##. #.... .#... ....# #...# #...# .##.. .##.. ..#.. ..... ..#.. #...#",
    "#..## ..#.. ....# ..#.. .#.#. ####. #.... ...#. #...# #...# .##.. .##.. .#... ##### ...#. ....#",
    "#.#.# ..#.. ...#. ...#. #..#. ....# ####. ..#.. .###. .#### ..... ..... #.... ..... ....# ...#.",
    "##..# ..#.. ..#.. ....# ##### ....# #...# .#... #...# ....# .##.. .##.. .#... ##### ...#. ..#..",
    "#...# ..#.. .#... #...# ...#. #...# #...# .#... #...# ...#. .##.. ..#.. ..#.. ..... ..#.. .....",
    ".###. .###. ##### .###. ...#. .###. .###. .#... .###. .##.. ..... .#... ...#. ..... .#... ..#..",
    "..... ..... ..... ..... ..... ..... ..... ..... ..... ..... ..... ..... ..... ..... ..... .....",
    /* '@'   'A'   'B'   'C'   'D'   'E'   'F'   'G'   'H'   'I'   'J'   'K'   'L'   'M'   'N'   'O'   */
    ".###. .###. ####. .###. ###.. ##### ##### .###. #...# .###. ..### #...# #.... #...# #...# .###.",
    "#...# #...# #...# #...# #..#. #.... #.... #...# #...# ..#.. ...#. #..#. #.... ##.## #...# #...#",
    "....# #...# #...# #.... #...# #.... #.... #.... #...# ..#.. ...#. #.#.. #.... #.#.# ##..# #...#",
    ".##.# ##### ####. #.... #...# ####. ####. #.### ##### ..#.. ...#. ##... #.... #.#.# #.#.# #...#",
    "#.#.# #...# #...# #.... #...# #.... #.... #...# #...# ..#.. ...#. #.#.. #.... #...# #..## #...#",
    "#.#.# #...# #...# #...# #..#. #.... #.... #...# #...# ..#.. #..#. #..#. #.... #...# #...# #...#",
    ".###. #...# ####. .###. ###.. ##### #.... .#### #...# .###. .##.. #...# ##### #...# #...# .###.",
    "..... ..... ..... ..... ..... ..... ..... ..... ..... ..... ..... ..... ..... ..... ..... .....",
    /* 'P'   'Q'   'R'   'S'   'T'   'U'   'V'   'W'   'X'   'Y'   'Z'   '['   '\\'  ']'   '^'   '_'   */
    "####. .###. ####. .#### ##### #...# #...# #...# #...# #...# ##### .###. ..... .###. ..#.. .....",
    "#...# #...# #...# #.... ..#.. #...# #...# #...# #...# #...# ....# .#... #.... ...#. .#.#. .....",
    "#...# #...# #...# #.... ..#.. #...# #...# #...# .#.#. .#.#. ...#. .#... .#... ...#. #...# .....",
    "####. #...# ####. .###. ..#.. #...# #...# #.#.# ..#.. ..#.. ..#.. .#... ..#.. ...#. ..... .....",
    "#.... #.#.# #.#.. ....# ..#.. #...# #...# #.#.# .#.#. ..#.. .#... .#... ...#. ...#. ..... .....",
    "#.... #..#. #..#. ....# ..#.. #...# .#.#. #.#.# #...# ..#.. #.... .#... ....# ...#. ..... .....",
    "#.... .##.# #...# ####. ..#.. .###. ..#.. .#.#. #...# ..#.. ##### .###. ..... .###. ..... .....",
    "..... ..... ..... ..... ..... ..... ..... ..... ..... ..... ..... ..... ..... ..... ..... #####",
    /* '`'   'a'   'b'   'c'   'd'   'e'   'f'   'g'   'h'   'i'   'j'   'k'   'l'   'm'   'n'   'o'   */
    ".#... ..... #.... ..... ....# ..... ..##. ..... #.... ..#.. ...#. #.... .##.. ..... ..... .....",
    "..#.. ..... #.... ..... ....# ..... .#..# ..... #.... ..... ..... #.... ..#.. ..... ..... .....",
    "...#. .###. #.##. .###. .##.# .###. .#... .#### #.##. .##.. ..##. #..#. ..#.. ##.#. #.##. .###.",
    "..... ....# ##..# #.... #..## #...# ###.. #...# ##..# ..#.. ...#. #.#.. ..#.. #.#.# ##..# #...#",
    "..... .#### #...# #.... #...# ##### .#... #...# #...# ..#.. ...#. ##... ..#.. #.#.# #...# #...#",
    "..... #...# #...# #...# #...# #.... .#... .#### #...# ..#.. ...#. #.#.. ..#.. #...# #...# #...#",
    "..... .#### ####. .###. .#### .###. .#... ....# #...# .###. #..#. #..#. .###. #...# #...# .###.",
    "..... ..... ..... ..... ..... ..... ..... .###. ..... ..... .##.. ..... ..... ..... ..... .....",
    /* 'p'   'q'   'r'   's'   't'   'u'   'v'   'w'   'x'   'y'   'z'   '{'   '|'   '}'   '~'   */
    "..... ..... ..... ..... .#... ..... ..... ..... ..... ..... ..... ...#. ..#.. .#... .....",
    "..... ..... ..... ..... .#... ..... ..... ..... ..... ..... ..... ..#.. ..#.. ..#.. .....",
    "####. .#### #.##. .#### ###.. #...# #...# #...# #...# #...# ##### ..#.. ..#.. ..#.. .#...",
    "#...# #...# ##..# #.... .#... #...# #...# #...# .#.#. #...# ...#. .#... ..#.. ...#. #.#.#",
    "#...# #...# #.... .###. .#... #...# #...# #.#.# ..#.. #...# ..#.. ..#.. ..#.. ..#.. ...#.",
    "####. .#### #.... ....# .#..# #..## .#.#. #.#.# .#.#. .#### .#... ..#.. ..#.. ..#.. .....",
    "#.... ....# #.... ####. ..##. .##.# ..#.. .#.#. #...# ....# ##### ...#. ..#.. .#... .....",
    "#.... ....# ..... ..... ..... ..... ..... ..... ..... .###. ..... ..... ..... ..... .....",
};

void sss_font_glyph(int ch, uint8_t rows[SSS_FONT_GLYPH_H])
{
    if (ch < 32 || ch > 126) ch = '?';
    int i = ch - 32, band = i / PER_BAND, col = i % PER_BAND;
    for (int r = 0; r < SSS_FONT_GLYPH_H; r++) {
        const char *s = font_art[band * CELL_H + r] + col * CELL_W;
        uint8_t bits = 0;
        for (int c = 0; c < SSS_FONT_GLYPH_W; c++) bits = (uint8_t)(bits << 1 | (s[c] == '#'));
        rows[r] = bits;
    }
}

int sss_font_text_width(const char *s, int scale)
{
    int best = 0, n = 0;
    for (; *s; s++) {
        if (*s == '\n') n = 0;
        else if (++n > best) best = n;
    }
    return best * SSS_FONT_ADVANCE * scale;
}

/* One vertex of a quad: pixel position, atlas coordinates, colour. */
typedef struct vtx {
    float x, y, u, v, r, g, b, a;
} vtx;

struct sss_text {
    GLuint prog, vao, vbo, tex;
    GLint loc_size;
    vtx *v;
    size_t n, cap;
    int width, height;
};

sss_result sss_text_create(sss_text **out, sss_error *err)
{
    *out = NULL;
    sss_text *t = calloc(1, sizeof *t);
    if (!t) return sss_fail(err, SSS_ERR_NOMEM, "overlay: out of memory");
    t->prog = sss_gl_program(sss_glsl_text_vert, sss_glsl_text_frag, err);
    if (!t->prog) {
        sss_text_destroy(t);
        return SSS_ERR_UNSUPPORTED;
    }
    t->loc_size = glGetUniformLocation(t->prog, "u_size");

    /* The atlas: one byte per pixel, 255 where a glyph pixel is lit. */
    uint8_t atlas[ATLAS_H][ATLAS_W];
    memset(atlas, 0, sizeof atlas);
    for (int ch = 32; ch <= 126; ch++) {
        uint8_t rows[SSS_FONT_GLYPH_H];
        sss_font_glyph(ch, rows);
        int i = ch - 32, x0 = (i % PER_BAND) * CELL_W, y0 = (i / PER_BAND) * CELL_H;
        for (int r = 0; r < SSS_FONT_GLYPH_H; r++)
            for (int c = 0; c < SSS_FONT_GLYPH_W; c++)
                if (rows[r] >> (SSS_FONT_GLYPH_W - 1 - c) & 1) atlas[y0 + r][x0 + c] = 255;
    }
    for (int r = 0; r < CELL_H; r++)
        for (int c = 0; c < CELL_W; c++)
            atlas[(SOLID_CELL / PER_BAND) * CELL_H + r][(SOLID_CELL % PER_BAND) * CELL_W + c] = 255;
    glGenTextures(1, &t->tex);
    glBindTexture(GL_TEXTURE_2D, t->tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1); /* rows are 96 bytes, but say so rather than rely on it */
    glTexImage2D(GL_TEXTURE_2D, 0, GL_R8, ATLAS_W, ATLAS_H, 0, GL_RED, GL_UNSIGNED_BYTE, atlas);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    /* nearest: glyphs are drawn at integer scales on integer pixel positions, crisp */
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glBindTexture(GL_TEXTURE_2D, 0);

    glGenVertexArrays(1, &t->vao);
    glBindVertexArray(t->vao);
    glGenBuffers(1, &t->vbo);
    glBindBuffer(GL_ARRAY_BUFFER, t->vbo);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, sizeof(vtx), (void *)offsetof(vtx, x));
    glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, sizeof(vtx), (void *)offsetof(vtx, u));
    glVertexAttribPointer(2, 4, GL_FLOAT, GL_FALSE, sizeof(vtx), (void *)offsetof(vtx, r));
    for (GLuint k = 0; k < 3; k++) glEnableVertexAttribArray(k);
    glBindVertexArray(0);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    *out = t;
    return SSS_OK;
}

void sss_text_destroy(sss_text *t)
{
    if (!t) return;
    if (t->prog) glDeleteProgram(t->prog);
    if (t->vbo) glDeleteBuffers(1, &t->vbo);
    if (t->vao) glDeleteVertexArrays(1, &t->vao);
    if (t->tex) glDeleteTextures(1, &t->tex);
    free(t->v);
    free(t);
}

void sss_text_begin(sss_text *t, int width, int height)
{
    t->n = 0;
    t->width = width;
    t->height = height;
}

/* Appends a quad (two triangles) covering [x0,x1]×[y0,y1] in pixels and
 * [u0,u1]×[v0,v1] in the atlas. Quietly drops it if memory runs out: a
 * missing overlay line is better than a dead viewer. */
static void quad(sss_text *t, float x0, float y0, float x1, float y1, float u0, float v0, float u1, float v1,
                 const float c[4])
{
    if (t->n + 6 > t->cap) {
        size_t cap = t->cap ? 2 * t->cap : 6 * 256;
        vtx *v = realloc(t->v, cap * sizeof *v);
        if (!v) return;
        t->v = v;
        t->cap = cap;
    }
    const float xy[6][4] = {{x0, y0, u0, v0}, {x1, y0, u1, v0}, {x1, y1, u1, v1},
                            {x0, y0, u0, v0}, {x1, y1, u1, v1}, {x0, y1, u0, v1}};
    for (int k = 0; k < 6; k++)
        t->v[t->n++] = (vtx){xy[k][0], xy[k][1], xy[k][2], xy[k][3], c[0], c[1], c[2], c[3]};
}

void sss_text_box(sss_text *t, float x, float y, float w, float h, const float rgba[4])
{
    /* the centre of the solid cell: every sample there is lit */
    float u = ((SOLID_CELL % PER_BAND) * CELL_W + 0.5f * CELL_W) / ATLAS_W;
    float v = ((SOLID_CELL / PER_BAND) * CELL_H + 0.5f * CELL_H) / ATLAS_H;
    quad(t, x, y, x + w, y + h, u, v, u, v, rgba);
}

void sss_text_print(sss_text *t, float x, float y, int scale, const float rgba[4], const char *s)
{
    if (scale < 1) scale = 1;
    float px = x, py = y;
    for (; *s; s++) {
        int ch = (unsigned char)*s;
        if (ch == '\n') {
            px = x;
            py += SSS_FONT_LINE * scale;
            continue;
        }
        if (ch < 32 || ch > 126) ch = '?';
        if (ch != ' ') {
            int i = ch - 32;
            float u0 = (float)((i % PER_BAND) * CELL_W) / ATLAS_W, v0 = (float)((i / PER_BAND) * CELL_H) / ATLAS_H;
            quad(t, px, py, px + CELL_W * scale, py + CELL_H * scale, u0, v0, u0 + (float)CELL_W / ATLAS_W,
                 v0 + (float)CELL_H / ATLAS_H, rgba);
        }
        px += SSS_FONT_ADVANCE * scale;
    }
}

void sss_text_flush(sss_text *t)
{
    if (!t->n || t->width < 1 || t->height < 1) return;
    GLint prog = 0, vao = 0, tex = 0, active = 0;
    glGetIntegerv(GL_CURRENT_PROGRAM, &prog);
    glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &vao);
    glGetIntegerv(GL_ACTIVE_TEXTURE, &active);
    glActiveTexture(GL_TEXTURE0);
    glGetIntegerv(GL_TEXTURE_BINDING_2D, &tex);
    GLboolean depth = glIsEnabled(GL_DEPTH_TEST), blend = glIsEnabled(GL_BLEND);

    glViewport(0, 0, t->width, t->height);
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glUseProgram(t->prog);
    glUniform2f(t->loc_size, (float)t->width, (float)t->height);
    glUniform1i(glGetUniformLocation(t->prog, "u_atlas"), 0);
    glBindTexture(GL_TEXTURE_2D, t->tex);
    glBindVertexArray(t->vao);
    glBindBuffer(GL_ARRAY_BUFFER, t->vbo);
    /* a fresh store every frame (orphaning): no wait on last frame's draw */
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(t->n * sizeof(vtx)), t->v, GL_STREAM_DRAW);
    glDrawArrays(GL_TRIANGLES, 0, (GLsizei)t->n);
    glBindBuffer(GL_ARRAY_BUFFER, 0);

    glBindVertexArray((GLuint)vao);
    glBindTexture(GL_TEXTURE_2D, (GLuint)tex);
    glActiveTexture((GLenum)active);
    glUseProgram((GLuint)prog);
    if (depth) glEnable(GL_DEPTH_TEST);
    if (!blend) glDisable(GL_BLEND);
}
