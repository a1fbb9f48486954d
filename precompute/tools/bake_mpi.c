/* bake_mpi.c: the MPI side of sss-bake (docs/benchmarks.md, "Bake at scale") and of sss-ref
 * (docs/reference.md §4). The libraries (libsss_bake) do not link MPI: they receive these
 * collectives through sss_bake_comm and sss_ref_comm. Parts are moved in chunks of at most 1 GiB, since MPI
 * counts are ints. */
#include "bake_mpi.h"

#include <stdlib.h>
#include <string.h>

#ifdef SSS_HAVE_MPI
#include <mpi.h>

static int active;

#define CHUNK ((uint64_t)1 << 30)

/* Bytes of the chunk at offset o of a part of len bytes. */
static int chunk(uint64_t len, uint64_t o) { return (int)(len - o < CHUNK ? len - o : CHUNK); }

static int allgather(void *buf, const uint64_t *offs, const uint64_t *lens, void *ctx)
{
    (void)ctx;
    int n;
    MPI_Comm_size(MPI_COMM_WORLD, &n);
    for (int r = 0; r < n; r++)
        for (uint64_t o = 0; o < lens[r]; o += CHUNK)
            if (MPI_Bcast((char *)buf + offs[r] + o, chunk(lens[r], o), MPI_BYTE, r, MPI_COMM_WORLD) != MPI_SUCCESS)
                return -1;
    return 0;
}

static int gather0(const void *part, void *full, const uint64_t *offs, const uint64_t *lens, void *ctx)
{
    (void)ctx;
    int n, me;
    MPI_Comm_size(MPI_COMM_WORLD, &n);
    MPI_Comm_rank(MPI_COMM_WORLD, &me);
    if (me != 0) {
        for (uint64_t o = 0; o < lens[me]; o += CHUNK)
            if (MPI_Send((const char *)part + o, chunk(lens[me], o), MPI_BYTE, 0, 8, MPI_COMM_WORLD) != MPI_SUCCESS)
                return -1;
        return 0;
    }
    if (lens[0]) memcpy((char *)full + offs[0], part, lens[0]);
    for (int r = 1; r < n; r++)
        for (uint64_t o = 0; o < lens[r]; o += CHUNK)
            if (MPI_Recv((char *)full + offs[r] + o, chunk(lens[r], o), MPI_BYTE, r, 8, MPI_COMM_WORLD,
                         MPI_STATUS_IGNORE) != MPI_SUCCESS)
                return -1;
    return 0;
}

static const sss_bake_comm comm = {allgather, gather0, NULL};

/* sss-ref: element-wise sums of the rounds' block sums (each element
 * non-zero on one rank only, so exact), in chunks of at most 2^27 doubles */
static int ref_allsum(double *buf, uint64_t n, void *ctx)
{
    (void)ctx;
    const uint64_t step = (uint64_t)1 << 27;
    for (uint64_t o = 0; o < n; o += step) {
        const int len = (int)(n - o < step ? n - o : step);
        if (MPI_Allreduce(MPI_IN_PLACE, buf + o, len, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD) != MPI_SUCCESS) return -1;
    }
    return 0;
}

static int ref_bcast(int *flag, void *ctx)
{
    (void)ctx;
    return MPI_Bcast(flag, 1, MPI_INT, 0, MPI_COMM_WORLD) == MPI_SUCCESS ? 0 : -1;
}

static const sss_ref_comm ref_comm = {ref_allsum, ref_bcast, NULL};

const sss_ref_comm *sss_mpi_ref_comm(void) { return active ? &ref_comm : NULL; }

void sss_mpi_start(int *argc, char ***argv, int *rank, int *nranks)
{
    *rank = 0;
    *nranks = 1;
    const char *a = getenv("OMPI_COMM_WORLD_SIZE"), *b = getenv("PMI_SIZE");
    if (!(a && *a) && !(b && *b)) return;
    if (MPI_Init(argc, argv) != MPI_SUCCESS) return;
    active = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, rank);
    MPI_Comm_size(MPI_COMM_WORLD, nranks);
}

const sss_bake_comm *sss_mpi_comm(void) { return active ? &comm : NULL; }

void sss_mpi_stop(void)
{
    if (active) MPI_Finalize();
    active = 0;
}

void sss_mpi_abort(int code)
{
    if (active) MPI_Abort(MPI_COMM_WORLD, code);
}

#else /* built without MPI: always one process */

void sss_mpi_start(int *argc, char ***argv, int *rank, int *nranks)
{
    (void)argc;
    (void)argv;
    *rank = 0;
    *nranks = 1;
}
const sss_bake_comm *sss_mpi_comm(void) { return NULL; }
const sss_ref_comm *sss_mpi_ref_comm(void) { return NULL; }
void sss_mpi_stop(void) {}
void sss_mpi_abort(int code) { (void)code; }

#endif
