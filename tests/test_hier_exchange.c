/* rad_hier's work shared among processes (rad_hier_exchange), without MPI:
 * threads stand in for the processes and an in-memory all-gather (two
 * barriers around the copies) for MPI_Allgatherv.  Every "process" must end
 * with the serial run's answer and figures bit for bit, for hier and
 * cluster, with the gather shared and replicated, on 2 and 3 processes (3:
 * shares of unequal size).  radkit-mpi's own runs are scripts/test_mpi.sh. */
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "rad_solve.h"

enum { MAX_PROCS = 4 };

typedef struct world {
    int size;
    pthread_barrier_t bar;
    unsigned char *buf[MAX_PROCS];
    long long calls[MAX_PROCS];
} world;

typedef struct proc {
    world *w;
    int rank, split;
    rad_solve_method method;
    rad_scene *scene;
    rad_solution *sol;
    rad_status st;
} proc;

static rad_status fake_allgather(void *ctx, void *buf, size_t item, const size_t *count,
                                 const size_t *offset)
{
    proc *p = ctx;
    world *w = p->w;
    w->buf[p->rank] = buf;
    w->calls[p->rank]++;
    pthread_barrier_wait(&w->bar); /* every buffer published */
    for (int r = 0; r < w->size; r++)
        if (r != p->rank)
            memcpy((unsigned char *)buf + offset[r] * item, w->buf[r] + offset[r] * item,
                   count[r] * item);
    pthread_barrier_wait(&w->bar); /* every copy made before a buffer changes */
    return RAD_OK;
}

static void params(rad_solve_params *sp, rad_solve_method method)
{
    rad_solve_params_default(sp);
    sp->method = method;
    sp->threads = 1;
    sp->hier.eps = 0.1;
}

static void *run(void *arg)
{
    proc *p = arg;
    rad_solve_params sp;
    params(&sp, p->method);
    sp.hier.exchange = (rad_hier_exchange){p->rank, p->w->size, fake_allgather, p, p->split};
    p->st = rad_solve_run(p->scene, &sp, &p->sol);
    return NULL;
}

static void shared_equals_serial(rad_solve_method method, int size, int split)
{
    rad_scene *scene = harness_scene_load("scenes/cornell/cornell.obj", NULL);
    if (!scene)
        return;
    rad_solve_params sp;
    params(&sp, method);
    rad_solution *ref = NULL;
    CHECK(rad_solve_run(scene, &sp, &ref) == RAD_OK);
    world w;
    memset(&w, 0, sizeof w);
    w.size = size;
    pthread_barrier_init(&w.bar, NULL, (unsigned)size);
    proc procs[MAX_PROCS];
    pthread_t tid[MAX_PROCS];
    for (int r = 0; r < size; r++) {
        procs[r] = (proc){&w, r, split, method, scene, NULL, RAD_OK};
        CHECK(pthread_create(&tid[r], NULL, run, &procs[r]) == 0);
    }
    for (int r = 0; r < size; r++)
        pthread_join(tid[r], NULL);
    pthread_barrier_destroy(&w.bar);
    for (int r = 0; r < size && ref; r++) {
        const rad_solution *s = procs[r].sol;
        CHECK_MSG(procs[r].st == RAD_OK && s, "process %d of %d: %s", r, size,
                  rad_strerror(procs[r].st));
        if (!s)
            continue;
        /* the exchange was used, the same number of times everywhere */
        CHECK(w.calls[r] > 0 && w.calls[r] == w.calls[0]);
        CHECK(s->faces == ref->faces);
        CHECK_MSG(memcmp(s->face_B, ref->face_B, 3 * (size_t)ref->faces * sizeof *s->face_B) == 0,
                  "process %d of %d (split %d): the radiosities differ from the serial run's",
                  r, size, split);
        CHECK(s->hier.links == ref->hier.links && s->hier.elements == ref->hier.elements);
        CHECK(s->hier.links_cluster == ref->hier.links_cluster);
        CHECK(s->kernel_evals == ref->kernel_evals && s->rays == ref->rays);
        CHECK(s->hier.iterations == ref->hier.iterations);
        CHECK(s->hier.bound_face_max == ref->hier.bound_face_max);
        CHECK(s->hier.time_comm_s >= 0.0);
    }
    for (int r = 0; r < size; r++)
        rad_solution_destroy(procs[r].sol);
    rad_solution_destroy(ref);
    rad_scene_destroy(scene);
}

TEST(hier_exchange_equals_serial)
{
    shared_equals_serial(RAD_SOLVE_HIER, 2, 1);
    shared_equals_serial(RAD_SOLVE_HIER, 3, 1);
    shared_equals_serial(RAD_SOLVE_HIER, 2, 0);
}

TEST(hier_exchange_cluster_equals_serial)
{
    shared_equals_serial(RAD_SOLVE_CLUSTER, 3, 1);
    shared_equals_serial(RAD_SOLVE_CLUSTER, 2, 0);
}

/* A failure reported by the exchange (another process left) ends the run
 * with that failure, not a hang or a wrong answer. */
static rad_status failing_allgather(void *ctx, void *buf, size_t item, const size_t *count,
                                    const size_t *offset)
{
    (void)buf, (void)item, (void)count, (void)offset;
    int *calls = ctx;
    if (++*calls >= 3)
        return RAD_ENUMERIC;
    return RAD_OK;
}

TEST(hier_exchange_failure_ends_the_run)
{
    rad_scene *scene = harness_scene_load("scenes/cornell/cornell.obj", NULL);
    if (!scene)
        return;
    int calls = 0;
    rad_solve_params sp;
    params(&sp, RAD_SOLVE_HIER);
    /* process 1 of 2 whose partner never answers: its own share only */
    sp.hier.exchange = (rad_hier_exchange){1, 2, failing_allgather, &calls, 1};
    rad_solution *s = NULL;
    CHECK(rad_solve_run(scene, &sp, &s) == RAD_ENUMERIC);
    CHECK(s == NULL && calls == 3);
    /* and an exchange without its function, or with a rank out of range, is refused */
    sp.hier.exchange = (rad_hier_exchange){0, 2, NULL, NULL, 0};
    CHECK(rad_solve_run(scene, &sp, &s) == RAD_EINVAL);
    sp.hier.exchange = (rad_hier_exchange){2, 2, failing_allgather, &calls, 0};
    CHECK(rad_solve_run(scene, &sp, &s) == RAD_EINVAL);
    rad_solution_destroy(s);
    rad_scene_destroy(scene);
}
