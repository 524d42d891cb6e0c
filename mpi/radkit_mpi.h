/* Internal to radkit-mpi: the hierarchical command (hier_mpi.c) and the
 * rad_hier_exchange over MPI it sets (exchange.c).  radkit_mpi.c's main
 * hands `solve --method hier|cluster` to radkit_mpi_hier. */
#ifndef RADKIT_MPI_H
#define RADKIT_MPI_H

#include <mpi.h>
#include <stddef.h>

#include "rad_error.h"
#include "rad_hier.h"

/* `radkit-mpi solve SCENE --method hier|cluster [radkit solve's options]
 * [--gather shared|replicated]`: every rank runs radkit solve's pipeline with
 * the exchange set, rank 0 prints.  Returns the process's exit code. */
int radkit_mpi_hier(int argc, char **argv, int rank, int ranks);

/* The exchange's state: its own communicator (so that no other collective
 * can match its calls), and the failure agreement.  Every collective the
 * library asks for is preceded by an all-reduce (MIN) of the number of the
 * lowest rank that failed by itself, `size` for none; a rank that fails by
 * itself leaves the pipeline and calls mpi_exchange_agree, whose all-reduce
 * meets the others' next one, so they return a failure too instead of
 * waiting in a collective it never joins. */
typedef struct mpi_exchange {
    MPI_Comm comm;
    int rank, size;
    int failed_rank; /* the lowest rank that failed by itself, or size */
    int *count, *offset; /* size each: the all-gather's blocks in items */
    double cpu_s;        /* processor time spent in the exchanges (waiting included:
                            Open MPI polls while it waits) */
} mpi_exchange;

/* This process's processor time, in seconds. */
double mpi_cpu_seconds(void);

/* A duplicate of MPI_COMM_WORLD and the buffers; RAD_ENOMEM (then every rank
 * must still call mpi_exchange_agree). */
rad_status mpi_exchange_init(mpi_exchange *x);
void mpi_exchange_destroy(mpi_exchange *x);
/* The library's hook (rad_hier_exchange) over x. */
void mpi_exchange_hook(mpi_exchange *x, int split_gather, rad_hier_exchange *hook);
/* After the pipeline: unless the hook already learned of a failure, the
 * all-reduce of who failed by itself (st != RAD_OK on this rank).  Returns
 * the lowest rank that failed, or size when none did; the same on every
 * rank. */
int mpi_exchange_agree(mpi_exchange *x, rad_status st);

#endif
