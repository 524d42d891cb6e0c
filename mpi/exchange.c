/* radkit-mpi: rad_hier_exchange over MPI (see radkit_mpi.h).  The library
 * asks for in-place all-gathers of blocks of fixed-size items; each is one
 * MPI_Allgatherv of a contiguous byte type, preceded by the failure
 * agreement's all-reduce. */
#include <limits.h>
#include <stdlib.h>
#include <time.h>

#include "radkit_mpi.h"

double mpi_cpu_seconds(void)
{
    struct timespec t;
    if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t) != 0)
        return 0.0;
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

rad_status mpi_exchange_init(mpi_exchange *x)
{
    MPI_Comm_rank(MPI_COMM_WORLD, &x->rank);
    MPI_Comm_size(MPI_COMM_WORLD, &x->size);
    x->failed_rank = x->size;
    x->count = x->offset = NULL;
    x->cpu_s = 0.0;
    if (MPI_Comm_dup(MPI_COMM_WORLD, &x->comm) != MPI_SUCCESS) {
        x->comm = MPI_COMM_NULL;
        return RAD_ERROR(RAD_ENUMERIC, "solve: MPI_Comm_dup failed");
    }
    x->count = malloc(2 * (size_t)x->size * sizeof *x->count);
    if (!x->count)
        return RAD_ERROR(RAD_ENOMEM, "solve: out of memory for %d ranks", x->size);
    x->offset = x->count + x->size;
    return RAD_OK;
}

void mpi_exchange_destroy(mpi_exchange *x)
{
    if (x->comm != MPI_COMM_NULL)
        MPI_Comm_free(&x->comm);
    free(x->count);
    x->count = x->offset = NULL;
}

/* The all-reduce of who failed by itself: mine = this rank or size. */
static int lowest_failed(mpi_exchange *x, int mine)
{
    int low = mine;
    if (MPI_Allreduce(&mine, &low, 1, MPI_INT, MPI_MIN, x->comm) != MPI_SUCCESS)
        return 0; /* (the default error handler aborts first) */
    return low;
}

static rad_status exchange(mpi_exchange *x, void *buf, size_t item_bytes, const size_t *count,
                           const size_t *offset);

/* The exchange with its processor time counted. */
static rad_status allgather(void *ctx, void *buf, size_t item_bytes, const size_t *count,
                            const size_t *offset)
{
    mpi_exchange *x = ctx;
    double c0 = mpi_cpu_seconds();
    rad_status st = exchange(x, buf, item_bytes, count, offset);
    x->cpu_s += mpi_cpu_seconds() - c0;
    return st;
}

static rad_status exchange(mpi_exchange *x, void *buf, size_t item_bytes, const size_t *count,
                           const size_t *offset)
{
    int low = lowest_failed(x, x->size);
    if (low < x->size) {
        x->failed_rank = low;
        return RAD_ERROR(RAD_ENUMERIC, "solve: rank %d failed", low);
    }
    /* the blocks are the same on every rank, so every rank refuses alike */
    for (int r = 0; r < x->size; r++) {
        if (count[r] > INT_MAX || offset[r] > INT_MAX)
            return RAD_ERROR(RAD_ETOOBIG, "solve: an exchange of %zu items is beyond MPI's "
                                          "int counts", count[r] + offset[r]);
        x->count[r] = (int)count[r];
        x->offset[r] = (int)offset[r];
    }
    if (item_bytes < 1 || item_bytes > INT_MAX)
        return RAD_ERROR(RAD_EINVAL, "solve: an item of %zu bytes", item_bytes);
    MPI_Datatype item;
    if (MPI_Type_contiguous((int)item_bytes, MPI_BYTE, &item) != MPI_SUCCESS ||
        MPI_Type_commit(&item) != MPI_SUCCESS)
        return RAD_ERROR(RAD_ENUMERIC, "solve: MPI could not make a type of %zu bytes",
                         item_bytes);
    int rc = MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_DATATYPE_NULL, buf, x->count, x->offset, item,
                            x->comm);
    MPI_Type_free(&item);
    if (rc != MPI_SUCCESS)
        return RAD_ERROR(RAD_ENUMERIC, "solve: MPI_Allgatherv failed (%d)", rc);
    return RAD_OK;
}

void mpi_exchange_hook(mpi_exchange *x, int split_gather, rad_hier_exchange *hook)
{
    hook->rank = x->rank;
    hook->size = x->size;
    hook->allgather = allgather;
    hook->ctx = x;
    hook->split_gather = split_gather;
}

int mpi_exchange_agree(mpi_exchange *x, rad_status st)
{
    if (x->failed_rank < x->size)
        return x->failed_rank;
    x->failed_rank = lowest_failed(x, st == RAD_OK ? x->size : x->rank);
    return x->failed_rank;
}
