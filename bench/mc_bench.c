/* bench/mc_bench: Monte Carlo radiosity's paths per second against Embree's
 * bare ray throughput on the same scene (compiled by bench/mc.sh).
 *
 * Embree alone: its own scene over the scene's triangles (float, robust, no
 * filters), rays from uniform points of area-weighted random triangles in
 * cosine-weighted directions about their normals (the rays paths trace),
 * rtcOccluded1 and rtcIntersect1 with an unbounded tfar, pre-built.  Then
 * rad_mc_solve on the same scene.  Per thread count (1, 2), best of 3:
 *   embree_occluded_Mrays_s, embree_intersect_Mrays_s
 *   mc_paths_s, rays_per_path (shadow and continuation rays: the mean path
 *   length in rays), bounces_per_path
 *   ratio = mc_paths_s x rays_per_path / embree_occluded_rays_s: the share of
 *   Embree's bare occlusion throughput a path's rays run at; the target
 *   "within 2x" is ratio >= 0.5. */
#include <embree3/rtcore.h>
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rad_error.h"
#include "rad_geom.h"
#include "rad_mc.h"
#include "rad_scene.h"
#include "rad_sys.h"
#include "rad_vis.h"

static double rnd(unsigned long long *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) * 0x1.0p-53;
}

static rad_vec3 corner(const double *xyz, const int *tri, int t, int k)
{
    const double *p = xyz + 3 * tri[3 * t + k];
    return rad_vec3_make(p[0], p[1], p[2]);
}

int main(int argc, char **argv)
{
    const char *path = argc > 1 ? argv[1] : "scenes/cornell/cornell.obj";
    long nrays = argc > 2 ? atol(argv[2]) : 4000000;
    long long samples = argc > 3 ? atoll(argv[3]) : 32768;
    rad_scene *scene = NULL;
    rad_scene_params sp;
    rad_scene_params_default(&sp);
    sp.no_cross_check = 1;
    if (rad_scene_load(path, &sp, &scene) != RAD_OK) {
        fprintf(stderr, "mc_bench: %s\n", rad_error_message());
        return 1;
    }
    int n = rad_scene_triangle_count(scene), nv = rad_scene_vertex_count(scene);
    const double *xyz = rad_scene_vertices(scene);
    const int *tri = rad_scene_triangles(scene), *mat = rad_scene_triangle_materials(scene);
    const rad_scene_material *mats = rad_scene_materials(scene);

    /* rays: area-weighted triangle, uniform point, cosine direction */
    double *cdf = malloc((size_t)n * sizeof *cdf), total = 0.0;
    for (int t = 0; t < n; t++)
        cdf[t] = total += rad_geom_triangle_area(corner(xyz, tri, t, 0), corner(xyz, tri, t, 1),
                                                 corner(xyz, tri, t, 2));
    float *org = malloc(3 * (size_t)nrays * sizeof *org), *dir = malloc(3 * (size_t)nrays * sizeof *dir);
    unsigned long long s = 2385;
    for (long r = 0; r < nrays; r++) {
        double u = rnd(&s) * total;
        int t = 0;
        while (t < n - 1 && cdf[t] < u)
            t++;
        rad_vec3 a = corner(xyz, tri, t, 0), b = corner(xyz, tri, t, 1), c = corner(xyz, tri, t, 2);
        double u1 = rnd(&s), u2 = rnd(&s);
        if (u1 + u2 > 1) {
            u1 = 1 - u1;
            u2 = 1 - u2;
        }
        rad_vec3 p = rad_geom_triangle_point(a, b, c, u1, u2), nn = rad_geom_triangle_normal(a, b, c);
        rad_vec3 h = fabs(nn.x) < 0.9 ? rad_vec3_make(1, 0, 0) : rad_vec3_make(0, 1, 0);
        rad_vec3 t1 = rad_vec3_cross(nn, h);
        t1 = rad_vec3_scale(t1, 1.0 / rad_vec3_norm(t1));
        rad_vec3 t2 = rad_vec3_cross(nn, t1);
        double r1 = rnd(&s), phi = 2 * RAD_PI * rnd(&s), rr = sqrt(r1);
        rad_vec3 d = rad_vec3_add(rad_vec3_add(rad_vec3_scale(t1, rr * cos(phi)),
                                               rad_vec3_scale(t2, rr * sin(phi))),
                                  rad_vec3_scale(nn, sqrt(1 - r1)));
        float *o = org + 3 * r, *w = dir + 3 * r;
        o[0] = (float)p.x; o[1] = (float)p.y; o[2] = (float)p.z;
        w[0] = (float)d.x; w[1] = (float)d.y; w[2] = (float)d.z;
    }

    RTCDevice dev = rtcNewDevice("threads=1,set_affinity=0");
    RTCScene es = rtcNewScene(dev);
    rtcSetSceneFlags(es, RTC_SCENE_FLAG_ROBUST);
    RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    float *fv = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, (size_t)nv);
    unsigned *fi = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12, (size_t)n);
    for (long q = 0; q < 3L * nv; q++)
        fv[q] = (float)xyz[q];
    for (long q = 0; q < 3L * n; q++)
        fi[q] = (unsigned)tri[q];
    rtcCommitGeometry(g);
    rtcAttachGeometry(es, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(es);

    rad_vis *vis = NULL;
    rad_vis_params vp;
    rad_vis_params_default(&vp);
    vp.eps_rel = 1e-6;
    if (rad_vis_create(xyz, (size_t)nv, tri, (size_t)n, &vp, &vis) != RAD_OK) {
        fprintf(stderr, "mc_bench: %s\n", rad_error_message());
        return 1;
    }
    float tnear = (float)(1e-6 * rad_vis_scale(vis));
    double *rho = malloc((size_t)n * 12 * sizeof *rho), *E = rho + 3 * n, *B = rho + 6 * n,
           *se = rho + 9 * n;
    for (int t = 0; t < n; t++)
        for (int c = 0; c < 3; c++) {
            rho[t + c * n] = mats[mat[t]].rho[c];
            E[t + c * n] = mats[mat[t]].emission[c];
        }

    printf("# mc bench: %s, %d triangles; Embree rays: %ld cosine-distributed rays from the "
           "surfaces; rad_mc: %lld paths per triangle; best of 3\n", path, n, nrays, samples);
    printf("threads\tembree_occluded_Mrays_s\tembree_intersect_Mrays_s\tmc_paths_s\t"
           "rays_per_path\tbounces_per_path\tratio\n");
    for (int threads = 1; threads <= 2; threads++) {
        omp_set_num_threads(threads);
        double best_occ = 0.0, best_int = 0.0, best_paths = 0.0, rays_per_path = 0.0,
               bounces = 0.0;
        for (int rep = 0; rep < 3; rep++) {
            long hits = 0;
            double t0 = rad_sys_seconds();
#pragma omp parallel for schedule(static) reduction(+ : hits)
            for (long r = 0; r < nrays; r++) {
                struct RTCIntersectContext ctx;
                rtcInitIntersectContext(&ctx);
                struct RTCRay ray;
                ray.org_x = org[3 * r]; ray.org_y = org[3 * r + 1]; ray.org_z = org[3 * r + 2];
                ray.dir_x = dir[3 * r]; ray.dir_y = dir[3 * r + 1]; ray.dir_z = dir[3 * r + 2];
                ray.tnear = tnear;
                ray.tfar = INFINITY;
                ray.time = 0.0f;
                ray.mask = 0xffffffffu;
                ray.id = 0;
                ray.flags = 0;
                rtcOccluded1(es, &ctx, &ray);
                hits += ray.tfar < 0.0f;
            }
            double t1 = rad_sys_seconds();
#pragma omp parallel for schedule(static) reduction(+ : hits)
            for (long r = 0; r < nrays; r++) {
                struct RTCIntersectContext ctx;
                rtcInitIntersectContext(&ctx);
                struct RTCRayHit rh;
                rh.ray.org_x = org[3 * r]; rh.ray.org_y = org[3 * r + 1]; rh.ray.org_z = org[3 * r + 2];
                rh.ray.dir_x = dir[3 * r]; rh.ray.dir_y = dir[3 * r + 1]; rh.ray.dir_z = dir[3 * r + 2];
                rh.ray.tnear = tnear;
                rh.ray.tfar = INFINITY;
                rh.ray.time = 0.0f;
                rh.ray.mask = 0xffffffffu;
                rh.ray.id = 0;
                rh.ray.flags = 0;
                rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
                rtcIntersect1(es, &ctx, &rh);
                hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
            }
            double t2 = rad_sys_seconds();
            rad_mc_params mp;
            rad_mc_params_default(&mp);
            mp.samples = samples;
            rad_mc_stats st;
            if (rad_mc_solve(xyz, (size_t)nv, tri, (size_t)n, rho, E, vis, &mp, B, se, &st) != RAD_OK) {
                fprintf(stderr, "mc_bench: %s\n", rad_error_message());
                return 1;
            }
            if (hits < 0)
                printf("never\n");
            best_occ = fmax(best_occ, nrays / (t1 - t0));
            best_int = fmax(best_int, nrays / (t2 - t1));
            best_paths = fmax(best_paths, st.paths / st.seconds);
            rays_per_path = (double)st.rays / st.paths;
            bounces = (double)st.bounces / st.paths;
        }
        printf("%d\t%.3f\t%.3f\t%.4g\t%.4f\t%.4f\t%.3f\n", threads, best_occ / 1e6, best_int / 1e6,
               best_paths, rays_per_path, bounces, best_paths * rays_per_path / best_occ);
    }
    rad_vis_destroy(vis);
    rtcReleaseScene(es);
    rtcReleaseDevice(dev);
    rad_scene_destroy(scene);
    free(cdf);
    free(org);
    free(dir);
    free(rho);
    return 0;
}
