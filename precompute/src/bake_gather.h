/* bake_gather.h: the bake's integrals phase through the hierarchical
 * gather (issue 8), called from bake.c. Not a public header. */
#ifndef SSS_BAKE_GATHER_H
#define SSS_BAKE_GATHER_H

#include "sss/bake.h"
#include "sss/gather.h"

/* SSS_GATHER_DIRECT or SSS_GATHER_TREE for these options and mesh size. */
int sss_bake_choose_gather(const sss_bake_options *o, uint32_t nv);

/* Visibility, tree and gather: fills out->q (rank 0 only under MPI) and the
 * stats' timings. avail: bytes that may be used (0: unknown); fixed: the
 * bytes of G, q and the quantiser already counted by bake.c. */
sss_result sss_bake_tree(const sss_mesh *mesh, const sss_material *mat, const sss_bake_options *o,
                         const sss_dipole *dip, uint32_t C, uint64_t avail, uint64_t fixed, sss_bake_file *out,
                         sss_bake_stats *st, sss_error *err);

#endif
