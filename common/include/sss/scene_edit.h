/* sss/scene_edit.h: an editable object's edited material written back to a
 * scene file (docs/heterogeneous.md §9.6): what sss-view's live edits (the
 * inside's σa, the field's strength, the base's transport colour) leave,
 * as a scene that loads, renders and bakes to the edited picture.
 */
#ifndef SSS_SCENE_EDIT_H
#define SSS_SCENE_EDIT_H

#include "sss/htsm.h"
#include "sss/result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The default target for the scene at path: NAME.edited.json next to it
 * (NAME the file's name less a ".json"), into out (size n); SSS_ERR_ARG
 * when it does not fit. */
sss_result sss_scene_edited_path(const char *path, char *out, size_t n, sss_error *err);

/* Whether out can take the edited scene of the scene at path, checked
 * before anything is drawn (sss-view --save-scene): out may be written
 * (sss_output_check: never the input) and its folder exists. Creates
 * nothing; one line naming out otherwise (SSS_ERR_IO). */
sss_result sss_scene_edited_check(const char *path, const char *out, sss_error *err);

/* Writes the scene at path again to out with object `object`'s material
 * replaced by m: the base's σa, σ′s and η as numbers, the inside's σa and
 * σ′s, the field as it was, and the strength s (f → min(1, s f)) folded
 * into the inside when s ≤ 1 (the blend is linear in f: the inside
 * becomes the blend at s, exactly), kept as the field's "strength" when
 * s > 1. Every other key stays as it was; when out lies in another folder,
 * the files the scene names (meshes, fields, probes) are written as
 * absolute paths. Atomic (sss/fileio.h): out is never the input, and a
 * failure leaves no file. Messages name the file. */
sss_result sss_scene_write_edited(const char *path, uint32_t object, const sss_htsm_material *m, const char *out,
                                  sss_error *err);

#ifdef __cplusplus
}
#endif
#endif
