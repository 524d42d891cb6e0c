/* rad_vis: the Embree scene and the point-to-point and closest-hit queries.
 *
 * 1. Copy the caller's vertices to double (for our exact tests) and to float
 *    (for Embree) and its indices to unsigned; both float and index buffers are
 *    handed to Embree with rtcSetSharedGeometryBuffer, padded by 16 bytes so
 *    Embree's SSE loads of the last element stay inside the allocation.
 * 2. The scene scale L = max(box diagonal, largest |coordinate|) fixes the ray
 *    epsilon eps = eps_rel L and the shaft tolerance tol = shaft_tol_rel L.
 * 3. One triangle geometry with mask VIS_MASK_OCCLUDER in a ROBUST scene (no
 *    leaks through shared edges of a blocker's triangles), with occlusion and
 *    intersection filters that drop hits on the primitives the query's context
 *    names (a pair query's own two triangles, a path vertex's triangle).
 * 4. Occlusion of a segment p -> q is one ray with origin p, direction q - p,
 *    tnear = eps / |q - p| and tfar = 1 - eps / |q - p|: the open segment
 *    shortened by eps at both ends.  Segments shorter than 2 eps are visible.
 * Embree 3 API: see the Embree 3 manual \cite{embree3manual, wald2014embree}. */
#include "vis_internal.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void rad_vis_params_default(rad_vis_params *params)
{
    memset(params, 0, sizeof *params); /* every field a later one adds starts at 0 */
    params->eps_rel = 1e-5;
    params->strata_per_edge = 3;
    params->jitter = 1;
    params->seed = 0x5eedu;
    params->build_threads = 1;
    params->packet = 16;
    params->shaft_tol_rel = 1e-9;
}

static rad_status check_params(const rad_vis_params *p)
{
    if (!(p->eps_rel > 0.0 && p->eps_rel < 0.01))
        return RAD_ERROR(RAD_EINVAL, "visibility: ray epsilon %g (relative) must lie in (0, 0.01)",
                         p->eps_rel);
    if (p->strata_per_edge < 1 || p->strata_per_edge > 64)
        return RAD_ERROR(RAD_EINVAL, "visibility: %d strata per edge; use 1 to 64",
                         p->strata_per_edge);
    if (p->build_threads < 1 || p->build_threads > 1024)
        return RAD_ERROR(RAD_EINVAL, "visibility: %d build threads", p->build_threads);
    if (p->packet != 1 && p->packet != 4 && p->packet != 8 && p->packet != 16)
        return RAD_ERROR(RAD_EINVAL, "visibility: packet size %d; use 1, 4, 8 or 16", p->packet);
    if (!(p->shaft_tol_rel >= 0.0 && p->shaft_tol_rel < 0.01))
        return RAD_ERROR(RAD_EINVAL, "visibility: shaft tolerance %g must lie in [0, 0.01)",
                         p->shaft_tol_rel);
    return RAD_OK;
}

void vis_context_init(vis_context *vc, unsigned ignore0, unsigned ignore1)
{
    rtcInitIntersectContext(&vc->ctx);
    vc->ignore[0] = ignore0;
    vc->ignore[1] = ignore1;
}

void vis_ignore_filter(const struct RTCFilterFunctionNArguments *args)
{
    const vis_context *vc = (const vis_context *)args->context;
    if (vc->ignore[0] == RTC_INVALID_GEOMETRY_ID && vc->ignore[1] == RTC_INVALID_GEOMETRY_ID)
        return;
    const unsigned *prim = (const unsigned *)args->hit + 5 * args->N; /* RTCHitN primID */
    for (unsigned l = 0; l < args->N; l++)
        if (args->valid[l] && (prim[l] == vc->ignore[0] || prim[l] == vc->ignore[1]))
            args->valid[l] = 0;
}

static rad_status embree_status(RTCDevice device, const char *what)
{
    enum RTCError code = rtcGetDeviceError(device);
    if (code == RTC_ERROR_NONE)
        return RAD_OK;
    if (code == RTC_ERROR_OUT_OF_MEMORY)
        return RAD_ERROR(RAD_ENOMEM, "visibility: Embree ran out of memory (%s)", what);
    return RAD_ERROR(RAD_EDEP, "visibility: Embree error %d during %s", (int)code, what);
}

void rad_vis_destroy(rad_vis *vis)
{
    if (!vis)
        return;
    if (vis->lock_ready)
        pthread_mutex_destroy(&vis->rays_lock);
    if (vis->scene)
        rtcReleaseScene(vis->scene);
    if (vis->device)
        rtcReleaseDevice(vis->device);
    free(vis->fverts);
    free(vis->findex);
    free(vis->xyz);
    free(vis->tri);
    free(vis->nodes);
    free(vis->order);
    free(vis->partner);
    free(vis->quad);
    free(vis->solid);
    free(vis->solids);
    free(vis->solid_tri);
    free(vis->solid_pt);
    free(vis->solid_plane);
    free(vis);
}

/* Embree's device and scene over the triangles (rad_vis_prepare_rays). */
static rad_status build_rays(rad_vis *vis)
{
    char config[64];
    snprintf(config, sizeof config, "threads=%d,set_affinity=0", vis->params.build_threads);
    vis->device = rtcNewDevice(config);
    if (!vis->device) {
        return RAD_ERROR(RAD_EDEP, "visibility: Embree could not create a device (%d)",
                         (int)rtcGetDeviceError(NULL));
    }
    vis->scene = rtcNewScene(vis->device);
    rad_status status = embree_status(vis->device, "scene creation");
    if (status != RAD_OK)
        return status;
    rtcSetSceneFlags(vis->scene, RTC_SCENE_FLAG_ROBUST);
    if (vis->ntris > 0) {
        RTCGeometry geom = rtcNewGeometry(vis->device, RTC_GEOMETRY_TYPE_TRIANGLE);
        if (!geom) {
            status = embree_status(vis->device, "geometry creation");
            return status != RAD_OK ? status
                                    : RAD_ERROR(RAD_EDEP, "visibility: Embree geometry creation failed");
        }
        rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                   vis->fverts, 0, 3 * sizeof(float), vis->nverts);
        rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                   vis->findex, 0, 3 * sizeof(unsigned), vis->ntris);
        rtcSetGeometryMask(geom, VIS_MASK_OCCLUDER);
        rtcSetGeometryOccludedFilterFunction(geom, vis_ignore_filter);
        rtcSetGeometryIntersectFilterFunction(geom, vis_ignore_filter);
        rtcCommitGeometry(geom);
        rtcAttachGeometryByID(vis->scene, geom, 0);
        rtcReleaseGeometry(geom);
    }
    rtcCommitScene(vis->scene);
    return embree_status(vis->device, "the BVH build");

}

rad_status rad_vis_prepare_rays(const rad_vis *cvis)
{
    if (!cvis)
        return RAD_ERROR(RAD_EINVAL, "visibility: NULL argument");
    rad_vis *vis = (rad_vis *)cvis; /* the ray structures are a cache: logically const */
    int state = __atomic_load_n(&vis->rays_state, __ATOMIC_ACQUIRE);
    if (state == 0) {
        pthread_mutex_lock(&vis->rays_lock);
        state = __atomic_load_n(&vis->rays_state, __ATOMIC_ACQUIRE);
        if (state == 0) {
            rad_status st = build_rays(vis);
            if (st != RAD_OK) {
                vis->rays_status = st;
                snprintf(vis->rays_message, sizeof vis->rays_message, "%s", rad_error_message());
            }
            state = st == RAD_OK ? 1 : 2;
            __atomic_store_n(&vis->rays_state, state, __ATOMIC_RELEASE);
        }
        pthread_mutex_unlock(&vis->rays_lock);
    }
    if (state == 2)
        return RAD_ERROR(vis->rays_status, "%s", vis->rays_message);
    return RAD_OK;
}

rad_status rad_vis_create(const double *xyz, size_t nverts, const int *tri, size_t ntris,
                          const rad_vis_params *params, rad_vis **out)
{
    rad_status status = RAD_OK;
    rad_vis *vis = NULL;
    if (!out || (!xyz && nverts) || (!tri && ntris))
        return RAD_ERROR(RAD_EINVAL, "visibility: NULL argument");
    *out = NULL;
    if (nverts > (size_t)INT32_MAX || ntris > (size_t)INT32_MAX / 3)
        return RAD_ERROR(RAD_ETOOBIG, "visibility: %zu vertices and %zu triangles exceed the "
                         "32-bit index range", nverts, ntris);
    rad_vis_params p;
    if (params)
        p = *params;
    else
        rad_vis_params_default(&p);
    if ((status = check_params(&p)) != RAD_OK)
        return status;

    vis = calloc(1, sizeof *vis);
    if (!vis)
        return RAD_ERROR(RAD_ENOMEM, "visibility: no memory");
    if (pthread_mutex_init(&vis->rays_lock, NULL) != 0) {
        free(vis);
        return RAD_ERROR(RAD_ENOMEM, "visibility: no lock for the ray structures");
    }
    vis->lock_ready = 1;
    vis->params = p;
    vis->nverts = nverts;
    vis->ntris = ntris;
    /* +4 floats / +4 indices: Embree may read 16 bytes from the last element. */
    vis->fverts = malloc((3 * nverts + 4) * sizeof *vis->fverts);
    vis->findex = malloc((3 * ntris + 4) * sizeof *vis->findex);
    vis->xyz = malloc((3 * nverts + 1) * sizeof *vis->xyz);
    vis->tri = malloc((3 * ntris + 1) * sizeof *vis->tri);
    if (!vis->fverts || !vis->findex || !vis->xyz || !vis->tri) {
        status = RAD_ERROR(RAD_ENOMEM, "visibility: no memory for %zu vertices", nverts);
        goto fail;
    }
    memset(vis->fverts + 3 * nverts, 0, 4 * sizeof *vis->fverts);
    memset(vis->findex + 3 * ntris, 0, 4 * sizeof *vis->findex);

    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    double maxabs = 0.0;
    for (size_t k = 0; k < 3 * nverts; k++) {
        if (!isfinite(xyz[k])) {
            status = RAD_ERROR(RAD_EINPUT, "visibility: vertex %zu has a non-finite coordinate", k / 3);
            goto fail;
        }
        vis->xyz[k] = xyz[k];
        vis->fverts[k] = (float)xyz[k];
        lo[k % 3] = fmin(lo[k % 3], xyz[k]);
        hi[k % 3] = fmax(hi[k % 3], xyz[k]);
        maxabs = fmax(maxabs, fabs(xyz[k]));
    }
    for (size_t k = 0; k < 3 * ntris; k++) {
        if (tri[k] < 0 || (size_t)tri[k] >= nverts) {
            status = RAD_ERROR(RAD_EINPUT, "visibility: triangle %zu refers to vertex %d, "
                               "outside 0..%zu", k / 3, tri[k], nverts ? nverts - 1 : 0);
            goto fail;
        }
        vis->tri[k] = tri[k];
        vis->findex[k] = (unsigned)tri[k];
    }
    /* Embree works in single precision, and its intersection tests multiply
       three coordinates: beyond 1e-12 .. 1e12 these products leave float's
       range and rays pass through walls or hit nothing.  Refused, never a
       silently wrong answer; the double-precision modules have no such limit. */
    double extent = nverts ? fmax(hi[0] - lo[0], fmax(hi[1] - lo[1], hi[2] - lo[2])) : 0.0;
    if (nverts && (maxabs > RAD_VIS_MAX_SIZE || (extent > 0.0 && extent < RAD_VIS_MIN_SIZE))) {
        status = RAD_ERROR(RAD_EINPUT, "visibility: the scene's size %.3g (largest coordinate "
                           "%.3g) is outside %g .. %g, what single precision ray tracing "
                           "(Embree) resolves; rescale the scene", extent, maxabs,
                           RAD_VIS_MIN_SIZE, RAD_VIS_MAX_SIZE);
        goto fail;
    }
    double diag = 0.0;
    if (nverts)
        diag = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                    (hi[2] - lo[2]) * (hi[2] - lo[2]));
    vis->scale = fmax(diag, maxabs);
    if (!(vis->scale > 0.0))
        vis->scale = 1.0; /* an empty or single-point scene: any scale will do */
    vis->eps = p.eps_rel * vis->scale;
    vis->tol = p.shaft_tol_rel * vis->scale;

    if (!vis_bvh_build(vis) || !vis_partners_build(vis) || (!p.no_solids && !vis_solids_build(vis))) {
        status = RAD_ERROR(RAD_ENOMEM, "visibility: no memory for the shaft hierarchy, the "
                                       "quad pairing or the solids");
        goto fail;
    }
    *out = vis;
    return RAD_OK;
fail:
    rad_vis_destroy(vis);
    return status;
}

double rad_vis_epsilon(const rad_vis *vis) { return vis ? vis->eps : 0.0; }
double rad_vis_scale(const rad_vis *vis) { return vis ? vis->scale : 0.0; }
size_t rad_vis_triangle_count(const rad_vis *vis) { return vis ? vis->ntris : 0; }
void rad_vis_triangle_corners(const rad_vis *vis, size_t t, rad_vec3 out[3])
{
    for (int v = 0; v < 3; v++)
        out[v] = vis_vertex(vis, t, v);
}
int rad_vis_is_unoccluded(const rad_vis *vis) { return vis ? vis->unoccluded : 0; }

/* Ray setup of one segment: returns 0 when the segment is too short to test. */
static int segment_ray(const rad_vis *vis, const double *p, const double *q, float org[3],
                       float dir[3], float *tnear, float *tfar)
{
    double d[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
    double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (!(len > 2.0 * vis->eps))
        return 0;
    for (int c = 0; c < 3; c++) {
        org[c] = (float)p[c];
        dir[c] = (float)d[c];
    }
    *tnear = (float)(vis->eps / len);
    *tfar = (float)(1.0 - vis->eps / len);
    return 1;
}

static void occluded_single(const rad_vis *vis, struct RTCIntersectContext *ctx, size_t n,
                            const double *from, const double *to, unsigned char *blocked,
                            unsigned long long *rays)
{
    for (size_t k = 0; k < n; k++) {
        struct RTCRay ray;
        float org[3], dir[3], tn, tf;
        blocked[k] = 0;
        if (!segment_ray(vis, from + 3 * k, to + 3 * k, org, dir, &tn, &tf))
            continue;
        ray.org_x = org[0]; ray.org_y = org[1]; ray.org_z = org[2];
        ray.dir_x = dir[0]; ray.dir_y = dir[1]; ray.dir_z = dir[2];
        ray.tnear = tn;
        ray.tfar = tf;
        ray.time = 0.0f;
        ray.mask = VIS_MASK_OCCLUDER;
        ray.id = 0;
        ray.flags = 0;
        rtcOccluded1(vis->scene, ctx, &ray);
        (*rays)++;
        blocked[k] = ray.tfar < 0.0f; /* Embree sets tfar = -inf on a hit */
    }
}

/* One packet function per width; Embree's RTCRayW is a structure of arrays. */
#define VIS_OCCLUDED_PACKET(W)                                                          \
    static void occluded_packet##W(const rad_vis *vis, struct RTCIntersectContext *ctx, \
                                   size_t n, const double *from, const double *to,      \
                                   unsigned char *blocked, unsigned long long *rays)    \
    {                                                                                   \
        for (size_t base = 0; base < n; base += W) {                                    \
            struct RTCRay##W ray;                                                       \
            int valid[W];                                                               \
            int any = 0;                                                                \
            for (int l = 0; l < W; l++) {                                               \
                size_t k = base + (size_t)l;                                            \
                float org[3] = {0, 0, 0}, dir[3] = {0, 0, 1}, tn = 0, tf = 0;           \
                valid[l] = k < n && segment_ray(vis, from + 3 * k, to + 3 * k, org,     \
                                                dir, &tn, &tf) ? -1 : 0;                \
                ray.org_x[l] = org[0]; ray.org_y[l] = org[1]; ray.org_z[l] = org[2];    \
                ray.dir_x[l] = dir[0]; ray.dir_y[l] = dir[1]; ray.dir_z[l] = dir[2];    \
                ray.tnear[l] = tn;                                                      \
                ray.tfar[l] = tf;                                                       \
                ray.time[l] = 0.0f;                                                     \
                ray.mask[l] = VIS_MASK_OCCLUDER;                                        \
                ray.id[l] = (unsigned)l;                                                \
                ray.flags[l] = 0;                                                       \
                any += valid[l] != 0;                                                   \
            }                                                                           \
            if (any)                                                                    \
                rtcOccluded##W(valid, vis->scene, ctx, &ray);                           \
            *rays += (unsigned long long)any;                                           \
            for (int l = 0; l < W && base + (size_t)l < n; l++)                         \
                blocked[base + (size_t)l] = valid[l] && ray.tfar[l] < 0.0f;             \
        }                                                                               \
    }
VIS_OCCLUDED_PACKET(4)
VIS_OCCLUDED_PACKET(8)
VIS_OCCLUDED_PACKET(16)

rad_status vis_occluded_ctx(const rad_vis *vis, vis_context *vc, size_t n, const double *from,
                            const double *to, unsigned char *blocked, unsigned long long *rays)
{
    rad_status st = rad_vis_prepare_rays(vis);
    if (st != RAD_OK)
        return st;
    switch (vis->params.packet) {
    case 4: occluded_packet4(vis, &vc->ctx, n, from, to, blocked, rays); break;
    case 8: occluded_packet8(vis, &vc->ctx, n, from, to, blocked, rays); break;
    case 16: occluded_packet16(vis, &vc->ctx, n, from, to, blocked, rays); break;
    default: occluded_single(vis, &vc->ctx, n, from, to, blocked, rays); break;
    }
    return RAD_OK;
}

rad_status rad_vis_occluded(const rad_vis *vis, size_t n, const double *from, const double *to,
                            unsigned char *blocked, rad_vis_stats *stats)
{
    if (!vis || (n && (!from || !to || !blocked)))
        return RAD_ERROR(RAD_EINVAL, "visibility: NULL argument to the occlusion query");
    vis_context vc;
    vis_context_init(&vc, RTC_INVALID_GEOMETRY_ID, RTC_INVALID_GEOMETRY_ID);
    unsigned long long rays = 0;
    rad_status st = vis_occluded_ctx(vis, &vc, n, from, to, blocked, &rays);
    if (stats)
        stats->rays += rays;
    return st;
}

rad_status rad_vis_occluded_between(const rad_vis *vis, size_t i, size_t j, size_t n,
                                    const double *from, const double *to, unsigned char *blocked,
                                    rad_vis_stats *stats)
{
    if (!vis || (n && (!from || !to || !blocked)))
        return RAD_ERROR(RAD_EINVAL, "visibility: NULL argument to the occlusion query");
    if (i >= vis->ntris || j >= vis->ntris)
        return RAD_ERROR(RAD_EINVAL, "visibility: bad pair (%zu, %zu) of %zu triangles", i, j,
                         vis->ntris);
    vis_context vc;
    vis_context_init(&vc, (unsigned)i, (unsigned)j);
    unsigned long long rays = 0;
    rad_status st = vis_occluded_ctx(vis, &vc, n, from, to, blocked, &rays);
    if (stats)
        stats->rays += rays;
    return st;
}

rad_status rad_vis_intersect(const rad_vis *vis, size_t n, const double *org, const double *dir,
                             double tnear, int *tri, double *t_hit, double *u, double *v,
                             rad_vis_stats *stats)
{
    if (!vis || (n && (!org || !dir || !tri)))
        return RAD_ERROR(RAD_EINVAL, "visibility: NULL argument to the intersection query");
    if (!(tnear >= 0.0) || !isfinite(tnear))
        return RAD_ERROR(RAD_EINVAL, "visibility: tnear %g must be finite and >= 0", tnear);
    rad_status st = rad_vis_prepare_rays(vis);
    if (st != RAD_OK)
        return st;
    vis_context vc;
    vis_context_init(&vc, RTC_INVALID_GEOMETRY_ID, RTC_INVALID_GEOMETRY_ID);
    for (size_t k = 0; k < n; k++) {
        struct RTCRayHit rh;
        memset(&rh, 0, sizeof rh);
        rh.ray.org_x = (float)org[3 * k];
        rh.ray.org_y = (float)org[3 * k + 1];
        rh.ray.org_z = (float)org[3 * k + 2];
        rh.ray.dir_x = (float)dir[3 * k];
        rh.ray.dir_y = (float)dir[3 * k + 1];
        rh.ray.dir_z = (float)dir[3 * k + 2];
        rh.ray.tnear = (float)tnear;
        rh.ray.tfar = INFINITY;
        rh.ray.mask = VIS_MASK_OCCLUDER;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(vis->scene, &vc.ctx, &rh);
        int hit = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
        tri[k] = hit ? (int)rh.hit.primID : -1;
        if (t_hit)
            t_hit[k] = hit ? rh.ray.tfar : INFINITY;
        if (u)
            u[k] = hit ? rh.hit.u : 0.0;
        if (v)
            v[k] = hit ? rh.hit.v : 0.0;
    }
    if (stats)
        stats->rays += n;
    return RAD_OK;
}

static unsigned ignore_id(int t) { return t < 0 ? RTC_INVALID_GEOMETRY_ID : (unsigned)t; }

int rad_vis_ray_closest(const rad_vis *vis, const double org[3], const double dir[3],
                        double tnear, int ignore, rad_vis_hit *hit)
{
    if (rad_vis_prepare_rays(vis) != RAD_OK) { /* the caller's prepare failed already */
        hit->tri = -1;
        hit->t = INFINITY;
        hit->u = hit->v = 0.0;
        return 0;
    }
    vis_context vc;
    vis_context_init(&vc, ignore_id(ignore), RTC_INVALID_GEOMETRY_ID);
    struct RTCRayHit rh;
    rh.ray.org_x = (float)org[0];
    rh.ray.org_y = (float)org[1];
    rh.ray.org_z = (float)org[2];
    rh.ray.dir_x = (float)dir[0];
    rh.ray.dir_y = (float)dir[1];
    rh.ray.dir_z = (float)dir[2];
    rh.ray.tnear = (float)tnear;
    rh.ray.tfar = INFINITY;
    rh.ray.time = 0.0f;
    rh.ray.mask = VIS_MASK_OCCLUDER;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(vis->scene, &vc.ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
        hit->tri = -1;
        hit->t = INFINITY;
        hit->u = hit->v = 0.0;
        return 0;
    }
    hit->tri = (int)rh.hit.primID;
    hit->t = rh.ray.tfar;
    hit->u = rh.hit.u;
    hit->v = rh.hit.v;
    return 1;
}

int rad_vis_segment_blocked_by(const rad_vis *vis, rad_vec3 p, rad_vec3 q, const int *blockers,
                               int n)
{
    rad_vec3 d = rad_vec3_sub(q, p);
    double len = rad_vec3_norm(d);
    if (!(len > 2.0 * vis->eps))
        return 0;
    double tn = vis->eps / len, tf = 1.0 - tn;
    for (int k = 0; k < n; k++) { /* Moller-Trumbore, edges and corners included */
        rad_vec3 v0 = vis_vertex(vis, (size_t)blockers[k], 0);
        rad_vec3 e1 = rad_vec3_sub(vis_vertex(vis, (size_t)blockers[k], 1), v0);
        rad_vec3 e2 = rad_vec3_sub(vis_vertex(vis, (size_t)blockers[k], 2), v0);
        rad_vec3 pv = rad_vec3_cross(d, e2);
        double det = rad_vec3_dot(e1, pv);
        if (!(fabs(det) > 1e-12 * len * rad_vec3_norm(e1) * rad_vec3_norm(e2)))
            continue; /* along its plane */
        double inv = 1.0 / det;
        rad_vec3 tv = rad_vec3_sub(p, v0);
        double u = rad_vec3_dot(tv, pv) * inv;
        if (!(u >= 0.0 && u <= 1.0))
            continue;
        rad_vec3 qv = rad_vec3_cross(tv, e1);
        double v = rad_vec3_dot(d, qv) * inv, t = rad_vec3_dot(e2, qv) * inv;
        if (v >= 0.0 && u + v <= 1.0 && t >= tn && t <= tf)
            return 1;
    }
    return 0;
}

int rad_vis_segment_blocked(const rad_vis *vis, const double p[3], const double q[3],
                            int ignore0, int ignore1)
{
    float org[3], dir[3], tn, tf;
    if (!segment_ray(vis, p, q, org, dir, &tn, &tf))
        return 0;
    if (rad_vis_prepare_rays(vis) != RAD_OK)
        return 1; /* the caller's prepare failed already */
    vis_context vc;
    vis_context_init(&vc, ignore_id(ignore0), ignore_id(ignore1));
    struct RTCRay ray;
    ray.org_x = org[0]; ray.org_y = org[1]; ray.org_z = org[2];
    ray.dir_x = dir[0]; ray.dir_y = dir[1]; ray.dir_z = dir[2];
    ray.tnear = tn;
    ray.tfar = tf;
    ray.time = 0.0f;
    ray.mask = VIS_MASK_OCCLUDER;
    ray.id = 0;
    ray.flags = 0;
    rtcOccluded1(vis->scene, &vc.ctx, &ray);
    return ray.tfar < 0.0f;
}
