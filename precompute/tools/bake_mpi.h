/* bake_mpi.h: sss-bake (docs/benchmarks.md, "Bake at scale") and sss-ref (docs/reference.md §4)
 * under mpirun. Built with MPI when CMake finds it (option SSS_MPI); otherwise every function says
 * "one process". */
#ifndef SSS_BAKE_MPI_H
#define SSS_BAKE_MPI_H

#include "sss/bake.h"
#include "sss/reference.h"

/* Starts MPI only when the process was launched by mpirun (OpenMPI's
 * OMPI_COMM_WORLD_SIZE or PMI_SIZE in the environment), so a plain
 * `sss-bake` never touches MPI. Sets *rank and *nranks (0 and 1 alone). */
void sss_mpi_start(int *argc, char ***argv, int *rank, int *nranks);
/* The collectives the bake uses (NULL when alone). */
const sss_bake_comm *sss_mpi_comm(void);
/* The collectives sss-ref's rounds use (NULL when alone). */
const sss_ref_comm *sss_mpi_ref_comm(void);
/* Ends MPI (no-op when alone). */
void sss_mpi_stop(void);
/* Stops every rank after a failure on one (no-op when alone). */
void sss_mpi_abort(int code);

#endif
