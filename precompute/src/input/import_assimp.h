/* import_assimp.h: private C interface to the C++17 Assimp adapter
 * (import_assimp.cpp). The glTF scanner (import_gltf.c) checks the file and
 * hands over a canonical GLB; Assimp's glTF 2.0 reader parses it and the
 * adapter places every mesh instance of the scene in world space.
 */
#ifndef SSS_IMPORT_ASSIMP_H
#define SSS_IMPORT_ASSIMP_H

#include <stddef.h>

#include "input/import_openmesh.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Parses the GLB data[0..len) (fmt is ignored: the signature is the
 * OpenMesh reader's, so the format table holds either). Every triangle
 * primitive under the scene's nodes is delivered once per instance, its
 * positions multiplied by the node's world transform (the product of its
 * ancestors' transforms, in double, rounded once to float), in the order
 * of a depth-first walk of the node tree, children in order. uv (v upward,
 * as Assimp delivers it) and rgba are filled when some primitive has them,
 * with (0, 0) and opaque white (glTF 2.0's default colour) for the others.
 * On failure *out is zeroed and msg holds one line. Never throws. */
sss_om_status sss_ai_read(const char *data, size_t len, sss_om_format fmt, sss_om_soup *out, char *msg,
                          size_t msglen);

#ifdef __cplusplus
}
#endif
#endif
