/* rad_hier: the work of one hierarchy shared among cooperating processes
 * (rad_hier_exchange, rad_hier.h).  The library never talks to another
 * process itself: the caller's allgather does (radkit-mpi: MPI_Allgatherv),
 * so the plain build needs no MPI.
 *
 * 1. Link estimates.  The jobs of a batch are dealt to the processes like
 *    cards (process r takes jobs r, r + size, ...: neighbouring jobs, which
 *    tend to cost alike, go to different processes, so the shares balance
 *    without a cost model); each process estimates its jobs into the
 *    batch's own slots, and one all-gather of the slots (and one of the
 *    flags saying which pairs face) gives every process the whole batch in
 *    job order.  Everything after it
 *    reads only the batch, so every process keeps the same links in the same
 *    order as the serial run: the hierarchies are equal bit for bit.
 * 2. The shared gather (split_gather).  The input triangles are cut into
 *    contiguous ranges balanced by the work of a step (the elements of each
 *    triangle's tree plus the link ends in it).  A process gathers, in link
 *    order, only the ends that lie in its own trees (every element's sum
 *    then has the serial terms in the serial order), pushes and pulls its
 *    own trees, and one all-gather of the elements' new values (ordered by
 *    owner, then index) makes every process's copy whole again.  The cluster
 *    links' gather stays replicated.
 * 3. Counters: each batch's kernel evaluations and rays are summed over the
 *    processes, so the statistics are the serial run's. */
#include "hier_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "rad_sys.h"

/* the values of an element an owner shares after a step: B (B, gB, Hn) or T */
enum { SHARE_B_DOUBLES = 15, SHARE_T_DOUBLES = 3 };

struct hier_share {
    unsigned long long version; /* the h->version this plan matches (when built) */
    int built;
    size_t root_lo, root_hi;    /* this process's input triangles */
    int *links;                 /* its links (indices into h->ln), in order */
    unsigned char *ends;        /* per such link: bit 1 a is its own, bit 2 b */
    size_t nlinks;
    int *order;                 /* every element, by owner, then index */
    size_t *count, *offset;     /* per process: its elements in `order` */
    size_t *root_cut;           /* size + 1 cuts of the input triangles */
    double *buf;                /* SHARE_B_DOUBLES per element */
    size_t cap_links, cap_el;
};

int hier_shared(const rad_hier *h)
{
    return h->p.exchange.size > 1 && h->p.exchange.allgather;
}

int hier_split_on(const rad_hier *h)
{
    return hier_shared(h) && h->p.exchange.split_gather;
}

void hier_share(const rad_hier *h, size_t *first, size_t *step)
{
    int shared = hier_shared(h);
    *first = shared ? (size_t)h->p.exchange.rank : 0;
    *step = shared ? (size_t)h->p.exchange.size : 1;
}

/* the allgather with its time counted; count/offset per process in items */
static rad_status gather(rad_hier *h, void *buf, size_t item_bytes, const size_t *count,
                         const size_t *offset)
{
    double t0 = rad_sys_seconds();
    const rad_hier_exchange *x = &h->p.exchange;
    rad_status st = x->allgather(x->ctx, buf, item_bytes, count, offset);
    h->st.time_comm_s += rad_sys_seconds() - t0;
    return st;
}

/* At most this many items per process go through the scratch array at once:
 * a batch's exchange then needs a few megabytes beside the batch, not a
 * second copy of it (the initial links of n triangles are n^2 / 2 jobs). */
enum { SHARE_CHUNK = 1 << 15 };

/* Process r's items are r, r + size, r + 2 size, ...: in chunks of
 * SHARE_CHUNK x size items (a multiple of size, so every chunk starts with
 * process 0's item), each packed into blocks of a scratch array in process
 * order, all-gathered, and dealt back. */
rad_status hier_share_gather(rad_hier *h, void *buf, size_t item_bytes, size_t n)
{
    int size = h->p.exchange.size, rank = h->p.exchange.rank;
    size_t z = (size_t)size, chunk = SHARE_CHUNK * z;
    size_t *count = malloc(2 * z * sizeof *count);
    unsigned char *tmp = malloc((n < chunk ? n : chunk) * item_bytes + 1), *b = buf;
    rad_status st = RAD_OK;
    if (!count || !tmp) {
        st = RAD_ERROR(RAD_ENOMEM, "hier: out of memory for an exchange of %zu items", n);
        goto done;
    }
    size_t *offset = count + size;
    for (size_t c0 = 0; c0 < n && st == RAD_OK; c0 += chunk) {
        size_t m = n - c0 < chunk ? n - c0 : chunk, at = 0;
        unsigned char *base = b + c0 * item_bytes;
        for (int r = 0; r < size; r++) {
            count[r] = (size_t)r < m ? (m - (size_t)r + z - 1) / z : 0;
            offset[r] = at;
            at += count[r];
        }
        for (size_t i = 0; i < count[rank]; i++)
            memcpy(tmp + (offset[rank] + i) * item_bytes,
                   base + ((size_t)rank + i * z) * item_bytes, item_bytes);
        if ((st = gather(h, tmp, item_bytes, count, offset)) != RAD_OK)
            break;
        for (int r = 0; r < size; r++)
            if (r != rank)
                for (size_t i = 0; i < count[r]; i++)
                    memcpy(base + ((size_t)r + i * z) * item_bytes,
                           tmp + (offset[r] + i) * item_bytes, item_bytes);
    }
done:
    free(count);
    free(tmp);
    return st;
}

/* An all-gather of one pair of 8-byte figures per process: pairs[2 r] and
 * pairs[2 r + 1] are process r's, this process's filled. */
static rad_status gather_pairs(rad_hier *h, void *pairs)
{
    int size = h->p.exchange.size;
    size_t *count = malloc(2 * (size_t)size * sizeof *count);
    if (!count)
        return RAD_ERROR(RAD_ENOMEM, "hier: out of memory for an exchange of %d processes", size);
    for (int r = 0; r < size; r++) {
        count[r] = 1;
        count[size + r] = (size_t)r;
    }
    rad_status st = gather(h, pairs, 16, count, count + size);
    free(count);
    return st;
}

rad_status hier_share_work(rad_hier *h, long long *evals, unsigned long long *rays)
{
    int size = h->p.exchange.size, rank = h->p.exchange.rank;
    /* one pair per process: its evaluations and its rays */
    unsigned long long *w = calloc(2 * (size_t)size, sizeof *w);
    if (!w)
        return RAD_ERROR(RAD_ENOMEM, "hier: out of memory for an exchange of %d processes", size);
    w[2 * rank] = (unsigned long long)*evals;
    w[2 * rank + 1] = *rays;
    rad_status st = gather_pairs(h, w);
    if (st == RAD_OK) {
        unsigned long long e = 0, r = 0;
        for (int k = 0; k < size; k++) {
            e += w[2 * k];
            r += w[2 * k + 1];
        }
        *evals = (long long)e;
        *rays = r;
    }
    free(w);
    return st;
}

void hier_share_destroy(rad_hier *h)
{
    struct hier_share *s = h->share;
    if (!s)
        return;
    free(s->links);
    free(s->ends);
    free(s->order);
    free(s->count);
    free(s->root_cut);
    free(s->buf);
    free(s);
    h->share = NULL;
}

/* Rebuilt on every process alike from the replicated hierarchy. */
rad_status hier_split_plan(rad_hier *h)
{
    int size = h->p.exchange.size, rank = h->p.exchange.rank;
    struct hier_share *s = h->share;
    if (!s) {
        s = h->share = calloc(1, sizeof *s);
        if (!s)
            return RAD_ERROR(RAD_ENOMEM, "hier: out of memory for the shared gather");
        s->count = malloc(2 * (size_t)size * sizeof *s->count);
        s->root_cut = malloc(((size_t)size + 1) * sizeof *s->root_cut);
        if (!s->count || !s->root_cut)
            return RAD_ERROR(RAD_ENOMEM, "hier: out of memory for the shared gather");
        s->offset = s->count + size;
    }
    if (s->built && s->version == h->version)
        return RAD_OK;
    s->built = 0;
    size_t n = h->nroots;
    /* the work of a step per input triangle: its elements and its link ends */
    double *cost = calloc(n, sizeof *cost);
    int *owner = malloc(n * sizeof *owner);
    if (!cost || !owner) {
        free(cost);
        free(owner);
        return RAD_ERROR(RAD_ENOMEM, "hier: out of memory for the shared gather");
    }
    for (size_t e = 0; e < h->nel; e++)
        cost[h->el[e].face] += 1.0;
    for (size_t k = 0; k < h->nln; k++)
        if (h->ln[k].a >= 0) {
            cost[h->el[h->ln[k].a].face] += 1.0;
            cost[h->el[h->ln[k].b].face] += 1.0;
        }
    double total = 0.0;
    for (size_t t = 0; t < n; t++)
        total += cost[t];
    /* process r takes the triangles whose cost before them reaches r / size of the total */
    double before = 0.0;
    int r = 0;
    s->root_cut[0] = 0;
    for (size_t t = 0; t < n; t++) {
        while (r + 1 < size && before >= total * (r + 1) / size)
            s->root_cut[++r] = t;
        owner[t] = r;
        before += cost[t];
    }
    while (r + 1 <= size)
        s->root_cut[++r] = n;
    s->root_lo = s->root_cut[rank];
    s->root_hi = s->root_cut[rank + 1];
    free(cost);
    rad_status st = RAD_OK;
    /* this process's links */
    if (h->nln > s->cap_links) {
        free(s->links);
        free(s->ends);
        s->links = malloc(h->nln * sizeof *s->links);
        s->ends = malloc(h->nln);
        s->cap_links = h->nln;
        if (!s->links || !s->ends) {
            s->cap_links = 0;
            st = RAD_ERROR(RAD_ENOMEM, "hier: out of memory for the shared gather");
            goto done;
        }
    }
    s->nlinks = 0;
    for (size_t k = 0; k < h->nln; k++) {
        const hier_link *l = &h->ln[k];
        if (l->a < 0)
            continue;
        unsigned char m = (unsigned char)((owner[h->el[l->a].face] == rank ? 1 : 0) |
                                          (owner[h->el[l->b].face] == rank ? 2 : 0));
        if (m) {
            s->links[s->nlinks] = (int)k;
            s->ends[s->nlinks++] = m;
        }
    }
    /* the elements by owner */
    if (h->nel > s->cap_el) {
        free(s->order);
        free(s->buf);
        s->order = malloc(h->nel * sizeof *s->order);
        s->buf = malloc(h->nel * SHARE_B_DOUBLES * sizeof *s->buf);
        s->cap_el = h->nel;
        if (!s->order || !s->buf) {
            s->cap_el = 0;
            st = RAD_ERROR(RAD_ENOMEM, "hier: out of memory for the shared gather");
            goto done;
        }
    }
    for (int q = 0; q < size; q++)
        s->count[q] = 0;
    for (size_t e = 0; e < h->nel; e++)
        s->count[owner[h->el[e].face]]++;
    size_t at = 0;
    for (int q = 0; q < size; q++) {
        s->offset[q] = at;
        at += s->count[q];
    }
    {
        size_t *fill = malloc((size_t)size * sizeof *fill);
        if (!fill) {
            st = RAD_ERROR(RAD_ENOMEM, "hier: out of memory for the shared gather");
            goto done;
        }
        memcpy(fill, s->offset, (size_t)size * sizeof *fill);
        for (size_t e = 0; e < h->nel; e++)
            s->order[fill[owner[h->el[e].face]]++] = (int)e;
        free(fill);
    }
    s->version = h->version;
    s->built = 1;
done:
    free(owner);
    return st;
}

const int *hier_split_links(const rad_hier *h, const unsigned char **ends, size_t *n)
{
    *ends = h->share->ends;
    *n = h->share->nlinks;
    return h->share->links;
}

void hier_split_roots(const rad_hier *h, size_t *lo, size_t *hi)
{
    *lo = h->share->root_lo;
    *hi = h->share->root_hi;
}

/* the largest of two step figures, a non-finite one kept (the caller reports it) */
static double worst(double a, double b)
{
    if (!isfinite(a))
        return a;
    if (!isfinite(b))
        return b;
    return a > b ? a : b;
}

rad_status hier_split_exchange(rad_hier *h, int carry, double *change, double *vmax)
{
    struct hier_share *s = h->share;
    int size = h->p.exchange.size, rank = h->p.exchange.rank;
    size_t m = carry == CARRY_B ? SHARE_B_DOUBLES : SHARE_T_DOUBLES;
    /* the step's figures first, one item per process */
    double fig[2 * 64], *f = size <= 64 ? fig : malloc(2 * (size_t)size * sizeof *f);
    rad_status st = RAD_OK;
    if (!f)
        return RAD_ERROR(RAD_ENOMEM, "hier: out of memory for an exchange of %d processes", size);
    f[2 * rank] = *change;
    f[2 * rank + 1] = *vmax;
    if ((st = gather_pairs(h, f)) != RAD_OK)
        goto done;
    for (int r = 0; r < size; r++) {
        *change = worst(*change, f[2 * r]);
        *vmax = worst(*vmax, f[2 * r + 1]);
    }
    /* then the elements' values, packed by owner */
    for (size_t i = s->offset[rank]; i < s->offset[rank] + s->count[rank]; i++) {
        const hier_elem *x = &h->el[s->order[i]];
        double *v = s->buf + i * m;
        if (carry == CARRY_B) {
            for (int k = 0; k < 3; k++) {
                v[k] = x->B[k];
                v[3 + 3 * k] = x->gB[k].x;
                v[4 + 3 * k] = x->gB[k].y;
                v[5 + 3 * k] = x->gB[k].z;
                v[12 + k] = x->Hn[k];
            }
        } else {
            memcpy(v, x->T, sizeof x->T);
        }
    }
    if ((st = gather(h, s->buf, m * sizeof *s->buf, s->count, s->offset)) != RAD_OK)
        goto done;
    for (int r = 0; r < size; r++) {
        if (r == rank)
            continue;
        for (size_t i = s->offset[r]; i < s->offset[r] + s->count[r]; i++) {
            hier_elem *x = &h->el[s->order[i]];
            const double *v = s->buf + i * m;
            if (carry == CARRY_B) {
                for (int k = 0; k < 3; k++) {
                    x->B[k] = v[k];
                    x->gB[k] = rad_vec3_make(v[3 + 3 * k], v[4 + 3 * k], v[5 + 3 * k]);
                    x->Hn[k] = v[12 + k];
                }
            } else {
                memcpy(x->T, v, sizeof x->T);
            }
        }
    }
done:
    if (f != fig)
        free(f);
    return st;
}
