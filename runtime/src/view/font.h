/* font.h: a tiny hand-drawn bitmap font (ASCII 32–126, 5×8 glyphs in 6×8
 * cells) and a text/box overlay drawn with OpenGL 4.3 core (one R8 atlas
 * texture, one VAO + VBO of textured quads, one small shader program).
 *
 * Usage per frame: sss_text_begin, any number of sss_text_box /
 * sss_text_print calls (appended in order, so boxes queued before text end
 * up behind it), then sss_text_flush to draw everything in one call.
 */
#ifndef SSS_FONT_H
#define SSS_FONT_H

#include <stdint.h>
#include "sss/result.h"

#define SSS_FONT_GLYPH_W 5 /* lit columns of a glyph */
#define SSS_FONT_GLYPH_H 8 /* rows: 7 above the baseline + 1 descender row */
#define SSS_FONT_ADVANCE 6 /* horizontal pen advance (one blank column) */
#define SSS_FONT_LINE 10   /* vertical advance between lines */

/* Row bitmaps of one character, top row first; bit 4 is the leftmost
 * column. Characters outside 32–126 give the glyph of '?'. */
void sss_font_glyph(int ch, uint8_t rows[SSS_FONT_GLYPH_H]);

/* Width in pixels of the longest line of s at integer scale. */
int sss_font_text_width(const char *s, int scale);

typedef struct sss_text sss_text;

/* Needs a current GL ≥ 4.3 core context. */
sss_result sss_text_create(sss_text **out, sss_error *err);
void sss_text_destroy(sss_text *t);

/* Starts a new batch for a framebuffer of width × height pixels
 * (coordinates below are in pixels, origin top-left, y down). */
void sss_text_begin(sss_text *t, int width, int height);
/* A solid rectangle; rgba is straight (not premultiplied) alpha. */
void sss_text_box(sss_text *t, float x, float y, float w, float h, const float rgba[4]);
/* Text with its top-left at (x, y); '\n' starts a new line. */
void sss_text_print(sss_text *t, float x, float y, int scale, const float rgba[4], const char *s);
/* Draws the batch alpha-blended over the bound framebuffer, without depth
 * test, then puts blending, depth test, program, VAO and texture binding
 * back as they were, so the scene renderer finds its state unchanged. */
void sss_text_flush(sss_text *t);

#endif
