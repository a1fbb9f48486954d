/* edit.h: sss-view --scene S.json [--offscreen --out IMG] with no .sss file
 * for a scene whose object is "editable": true (docs/heterogeneous.md §9):
 * nothing is baked; each frame seed 000's run-time path (sss/htsm_gpu.h)
 * computes q per pixel from the object's material and field, which the
 * window's keys edit live (J / K the inside's absorption, U / I the field's
 * strength, Y the base's transport colour). */
#ifndef SSS_VIEW_EDIT_H
#define SSS_VIEW_EDIT_H

#include "pose.h"

/* 1 when the scene at path loads and its first object is editable. */
int sss_edit_wanted(const char *scene_path);

/* One frame offscreen into v->out (v->scene, size, exposure as for a
 * pose); the exit status (0; 1 after a failure; 2 for a scene it cannot
 * draw), messages in one line each. */
int sss_edit_offscreen(const sss_pose_view *v, sss_view_params *p);

/* The window, its material edited by keys. */
int sss_edit_window(const sss_pose_view *v, sss_view_params *p);

#endif
