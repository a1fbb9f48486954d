/* sss/precompute.h: every public header of libsss_bake, the precompute
 * library, in the order of its stages (docs/architecture.md): input,
 * kernels, gather, the pipeline and scene bakes, compression, measurement,
 * the path-traced reference.
 * Include the one header a file needs where that is enough.
 */
#ifndef SSS_PRECOMPUTE_H
#define SSS_PRECOMPUTE_H

#include "sss/import.h"
#include "sss/probe.h"
#include "sss/depthmap.h"

#include "sss/fieldweights.h"
#include "sss/nbhd.h"
#include "sss/visibility.h"
#include "sss/transfer.h"
#include "sss/lloyd.h"
#include "sss/gather.h"

#include "sss/bake.h"
#include "sss/planner.h"
#include "sss/bake_scene.h"
#include "sss/layer_depths.h"
#include "sss/perframe.h"

#include "sss/refs.h"
#include "sss/compress.h"

#include "sss/exact.h"
#include "sss/reconstruct.h"
#include "sss/vertex_error.h"

#include "sss/reference.h"

#endif
