/* rad_hier: the table of input-triangle pairs (rad_hier_pairs_*).
 *
 * A sub-element pair's shaft lies inside its input pair's, so what the
 * input pair's shaft test says (nothing can block it: rad_vis_pair_can_block)
 * holds for every pair of elements under it, and so does the contact test's
 * (the two cannot touch: rad_ff_triangles_touch).  Each entry is made the
 * first time a link estimate asks for it: the initial link of the pair
 * itself, which walks the same shaft to list its blockers and hands the
 * answer over (no second walk), and a pair that faces away is never asked.
 * Both orders of a pair share one byte (the lower index first, a triangular
 * table), so an entry is made, and seen made, for both at once.  Threads
 * that ask for the same entry at once compute the same byte, stored and read
 * atomically (a process sharing a solve makes the entries of the initial
 * links it did not estimate when it first meets them). */
#include "hier_internal.h"

#include <stdlib.h>

#include "rad_ff.h"

enum { PAIR_KNOWN = 4 };

struct rad_hier_pairs {
    const rad_vis *vis; /* over the input triangles: their corners */
    size_t n;
    unsigned char *bits; /* n (n + 1) / 2, one per unordered pair (slot), 0 until known */
};

rad_hier_pairs *rad_hier_pairs_create(const rad_vis *vis)
{
    rad_hier_pairs *t = calloc(1, sizeof *t);
    if (!t)
        return NULL;
    t->vis = vis;
    t->n = rad_vis_triangle_count(vis);
    if (!(t->bits = calloc(t->n ? t->n * (t->n + 1) / 2 : 1, 1))) {
        free(t);
        return NULL;
    }
    return t;
}

void rad_hier_pairs_destroy(rad_hier_pairs *t)
{
    if (t)
        free(t->bits);
    free(t);
}

/* rad_ff_triangles_touch of input triangles r and s (the centroid and the
 * longest edge as the elements have them). */
static int touch(const rad_vis *vis, int r, int s)
{
    rad_vec3 a[3], b[3];
    rad_vis_triangle_corners(vis, (size_t)r, a);
    rad_vis_triangle_corners(vis, (size_t)s, b);
    return rad_ff_triangles_touch(a, rad_geom_triangle_centroid(a[0], a[1], a[2]),
                                  rad_geom_triangle_longest_edge(a), b,
                                  rad_geom_triangle_centroid(b[0], b[1], b[2]),
                                  rad_geom_triangle_longest_edge(b));
}

/* The byte of the pair {lo, hi}, lo <= hi: row hi of the lower triangle. */
static size_t slot(int lo, int hi)
{
    return (size_t)hi * ((size_t)hi + 1) / 2 + (size_t)lo;
}

unsigned rad_hier_pairs_get(rad_hier_pairs *t, int r, int s, int can_block)
{
    int lo = r < s ? r : s, hi = r < s ? s : r; /* whichever order asks first, one answer */
    size_t i = slot(lo, hi);
    unsigned char v = __atomic_load_n(&t->bits[i], __ATOMIC_RELAXED);
    if (v & PAIR_KNOWN)
        return v & (RAD_HIER_PAIR_CAN_BLOCK | RAD_HIER_PAIR_MAY_TOUCH);
    if (can_block < 0)
        can_block = rad_vis_pair_can_block(t->vis, (size_t)lo, (size_t)hi);
    v = (unsigned char)((can_block ? RAD_HIER_PAIR_CAN_BLOCK : 0) |
                        (touch(t->vis, lo, hi) ? RAD_HIER_PAIR_MAY_TOUCH : 0));
    __atomic_store_n(&t->bits[i], (unsigned char)(v | PAIR_KNOWN), __ATOMIC_RELAXED);
    return v;
}

int rad_hier_pairs_known(const rad_hier_pairs *t, int r, int s)
{
    size_t i = r < s ? slot(r, s) : slot(s, r);
    return __atomic_load_n(&t->bits[i], __ATOMIC_RELAXED) & PAIR_KNOWN;
}
