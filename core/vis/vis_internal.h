/* Internal to rad_vis: the object's layout, shared by its source files. */
#ifndef VIS_INTERNAL_H
#define VIS_INTERNAL_H

#include <embree3/rtcore.h>
#include <pthread.h>

#include "rad_geom.h"
#include "rad_sys.h"
#include "rad_vis.h"

/* Every triangle of the scene carries this mask; every ray sets it too, so a
 * later caller can add geometry (e.g. emitters seen only by primary rays) on
 * other bits without rad_vis's occlusion rays seeing it. */
#define VIS_MASK_OCCLUDER 0x1u

/* A node of the bounding-volume hierarchy used by the shaft test. */
typedef struct vis_node {
    double lo[3], hi[3];
    int left, right; /* children, or -1 for a leaf */
    int first, count; /* leaf: order[first .. first+count) */
} vis_node;

struct rad_vis {
    /* Embree's device and scene are made by the first query that casts a ray
       (rad_vis_prepare_rays), under rays_lock: a run that clips its
       visibility exactly, or needs none, never pays for them */
    RTCDevice device;
    RTCScene scene;
    pthread_mutex_t rays_lock;
    int lock_ready;
    int rays_state;     /* 0: not made, 1: ready, 2: failed (atomic loads and stores) */
    rad_status rays_status;
    char rays_message[256];
    float *fverts;      /* the float copy Embree reads (shared buffer) */
    unsigned *findex;   /* the index copy Embree reads (shared buffer) */
    double *xyz;        /* the double copy our own tests use */
    int *tri;
    size_t nverts, ntris;
    rad_vis_params params;
    double scale, eps, tol;
    int unoccluded;
    vis_node *nodes;    /* hierarchy over the potential blockers only */
    int nnodes;
    int *order;         /* blocker triangle indices in BVH leaf order */
    size_t blockers;    /* triangles not on a supporting plane of the scene */
    int *partner;       /* per triangle, the one it makes a convex quad with, or -1 */
    int (*quad)[4];     /* that quad's corners (vertex indices), counter-clockwise */
    int *solid;         /* per triangle, the closed convex solid it bounds, or -1 (solid.c);
                           NULL: the scene has none */
    struct vis_solid *solids;
    int *solid_tri;     /* each solid's triangles, */
    int *solid_pt;      /* its distinct corners (vertex indices), */
    double *solid_plane; /* and per triangle its plane (m, c): the solid lies in m.p <= c */
};

/* Solids of at most this many triangles are found (solid.c). */
#define VIS_SOLID_MAX_TRIS 64

/* A closed convex solid: its triangles solid_tri[tri .. tri + ntri) (planes
 * alike), its corners solid_pt[pt .. pt + npt), and a sphere around them. */
typedef struct vis_solid {
    int tri, ntri, pt, npt;
    double centre[3], radius; /* a sphere that holds it */
} vis_solid;

static inline rad_vec3 vis_vertex(const rad_vis *vis, size_t t, int corner)
{
    const double *p = vis->xyz + 3 * (size_t)vis->tri[3 * t + corner];
    return rad_vec3_make(p[0], p[1], p[2]);
}

/* Every occlusion query passes this context to Embree; the geometry's
 * occlusion filter (vis_ignore_filter) rejects hits on the two primitives
 * named here (RTC_INVALID_GEOMETRY_ID: none).  A geometry filter runs only on
 * candidate hits, whereas a context filter makes Embree choose a slower
 * traversal for every ray (papers/dense-radiosity.md). */
typedef struct vis_context {
    struct RTCIntersectContext ctx; /* first, so the filter can cast back */
    unsigned ignore[2];
} vis_context;

void vis_context_init(vis_context *vc, unsigned ignore0, unsigned ignore1);
void vis_ignore_filter(const struct RTCFilterFunctionNArguments *args);
/* The batched occlusion of rad_vis_occluded under a given context (what
 * rad_vis_prepare_rays returns when the rays cannot be made). */
rad_status vis_occluded_ctx(const rad_vis *vis, vis_context *vc, size_t n, const double *from,
                            const double *to, unsigned char *blocked, unsigned long long *rays);

/* partner.c */
/* Pair the triangles that make convex quads (partner, quad).  0: no memory. */
int vis_partners_build(rad_vis *vis);

/* solid.c */
/* Find the closed convex solids (solid, solids, ...).  0: no memory. */
int vis_solids_build(rad_vis *vis);

/* shaft.c */
/* Classify the triangles (which can block at all; is the scene unoccluded?)
 * and build the shaft hierarchy over the potential blockers.  0: no memory. */
int vis_bvh_build(rad_vis *vis);
/* The triangles in[0..n) that the shaft of triangles a and b does not dismiss,
 * in order, into out (which may be in); returns their count (0 for a flat
 * pair, whose kernel vanishes). */
/* Whether a triangle can block some segment between input triangles i and
 * j, whatever the kernel along it (rad_vis_pair_fraction's unweighted
 * share); rad_vis_pair_can_block counts only segments of positive kernel. */
int vis_pair_segments_can_block(const rad_vis *vis, size_t i, size_t j);

int vis_shaft_filter(const rad_vis *vis, const rad_vec3 a[3], const rad_vec3 b[3], const int *in,
                     int n, int *out);

#endif
