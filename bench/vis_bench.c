/* bench/vis_bench: rays per second of rad_vis against Embree's own
 * single-ray rtcOccluded1 on the same rays (compiled by bench/vis.sh).
 *
 * Scene: a closed box (each wall a k x k grid of quads, 2 triangles each) with
 * 27 small cubes inside, about 20k triangles; rays join random points of two
 * random triangles, as form-factor assembly does.  Rows:
 *   embree_occluded1   rtcOccluded1 on pre-built float rays (the reference)
 *   rad_vis_packetP    rad_vis_occluded from double end points, P = 1, 4, 8, 16
 *   rad_vis_pairs      rad_vis_pair_fraction on random pairs (81 rays a pair,
 *                      sampling, shaft test and own-triangle filter included)
 * each with 1 and 2 OpenMP threads (static chunks; best of 3 runs). */
#include <embree3/rtcore.h>
#include <omp.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rad_sys.h"
#include "rad_vis.h"

static double rnd(unsigned long long *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) * 0x1.0p-53;
}

typedef struct mesh {
    double *xyz;
    int *tri;
    int nv, nt, capv, capt;
} mesh;

static int add_vertex(mesh *m, double x, double y, double z)
{
    if (m->nv == m->capv) {
        m->capv = m->capv ? 2 * m->capv : 1024;
        m->xyz = realloc(m->xyz, 3 * (size_t)m->capv * sizeof *m->xyz);
    }
    m->xyz[3 * m->nv] = x;
    m->xyz[3 * m->nv + 1] = y;
    m->xyz[3 * m->nv + 2] = z;
    return m->nv++;
}

static void add_tri(mesh *m, int a, int b, int c)
{
    if (m->nt == m->capt) {
        m->capt = m->capt ? 2 * m->capt : 1024;
        m->tri = realloc(m->tri, 3 * (size_t)m->capt * sizeof *m->tri);
    }
    m->tri[3 * m->nt] = a;
    m->tri[3 * m->nt + 1] = b;
    m->tri[3 * m->nt + 2] = c;
    m->nt++;
}

/* A grid of k x k quads on the parallelogram o + s u + t v. */
static void add_grid(mesh *m, const double o[3], const double u[3], const double v[3], int k)
{
    int base = m->nv;
    for (int j = 0; j <= k; j++)
        for (int i = 0; i <= k; i++)
            add_vertex(m, o[0] + u[0] * i / k + v[0] * j / k, o[1] + u[1] * i / k + v[1] * j / k,
                       o[2] + u[2] * i / k + v[2] * j / k);
    for (int j = 0; j < k; j++)
        for (int i = 0; i < k; i++) {
            int a = base + j * (k + 1) + i;
            add_tri(m, a, a + 1, a + k + 2);
            add_tri(m, a, a + k + 2, a + k + 1);
        }
}

static void add_box(mesh *m, const double lo[3], const double hi[3], int k)
{
    double d[3] = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
    for (int axis = 0; axis < 3; axis++)
        for (int side = 0; side < 2; side++) {
            int a = (axis + 1) % 3, b = (axis + 2) % 3;
            double o[3] = {lo[0], lo[1], lo[2]}, u[3] = {0, 0, 0}, v[3] = {0, 0, 0};
            o[axis] = side ? hi[axis] : lo[axis];
            u[a] = d[a];
            v[b] = d[b];
            add_grid(m, o, u, v, k);
        }
}

int main(int argc, char **argv)
{
    long nrays = argc > 1 ? atol(argv[1]) : 2000000;
    int k = argc > 2 ? atoi(argv[2]) : 40;
    mesh m = {0};
    double lo[3] = {0, 0, 0}, hi[3] = {5.5, 5.5, 5.5};
    add_box(&m, lo, hi, k);
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++)
            for (int c = 0; c < 3; c++) {
                double l[3] = {1 + 1.5 * a, 1 + 1.5 * b, 1 + 1.5 * c};
                double h[3] = {l[0] + 0.6, l[1] + 0.6, l[2] + 0.6};
                add_box(&m, l, h, 4);
            }

    /* Random segments between random points of random triangles. */
    double *from = malloc(3 * (size_t)nrays * sizeof *from), *to = malloc(3 * (size_t)nrays * sizeof *to);
    unsigned long long s = 2385;
    for (long r = 0; r < nrays; r++)
        for (int end = 0; end < 2; end++) {
            int t = (int)(rnd(&s) * m.nt);
            double u = rnd(&s), v = rnd(&s);
            if (u + v > 1) {
                u = 1 - u;
                v = 1 - v;
            }
            const double *a = m.xyz + 3 * m.tri[3 * t], *b = m.xyz + 3 * m.tri[3 * t + 1],
                         *c = m.xyz + 3 * m.tri[3 * t + 2];
            double *p = (end ? to : from) + 3 * r;
            for (int q = 0; q < 3; q++)
                p[q] = a[q] + u * (b[q] - a[q]) + v * (c[q] - a[q]);
        }
    unsigned char *blocked = malloc((size_t)nrays);

    rad_vis *vis = NULL;
    rad_vis_params par;
    rad_vis_params_default(&par);
    if (rad_vis_create(m.xyz, (size_t)m.nv, m.tri, (size_t)m.nt, &par, &vis) != RAD_OK) {
        fprintf(stderr, "vis_bench: %s\n", rad_error_message());
        return 1;
    }
    double eps = rad_vis_epsilon(vis);

    /* Embree alone: same geometry, same rays as float RTCRay, same epsilon. */
    RTCDevice dev = rtcNewDevice("threads=1,set_affinity=0");
    RTCScene scene = rtcNewScene(dev);
    rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
    RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    float *fv = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, (size_t)m.nv);
    unsigned *fi = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12, (size_t)m.nt);
    for (long q = 0; q < 3L * m.nv; q++)
        fv[q] = (float)m.xyz[q];
    for (long q = 0; q < 3L * m.nt; q++)
        fi[q] = (unsigned)m.tri[q];
    rtcCommitGeometry(g);
    rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(scene);
    struct RTCRay *rays = malloc((size_t)nrays * sizeof *rays);
    for (long r = 0; r < nrays; r++) {
        double d[3] = {to[3 * r] - from[3 * r], to[3 * r + 1] - from[3 * r + 1], to[3 * r + 2] - from[3 * r + 2]};
        double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        struct RTCRay *ray = &rays[r];
        ray->org_x = (float)from[3 * r]; ray->org_y = (float)from[3 * r + 1]; ray->org_z = (float)from[3 * r + 2];
        ray->dir_x = (float)d[0]; ray->dir_y = (float)d[1]; ray->dir_z = (float)d[2];
        ray->tnear = len > 2 * eps ? (float)(eps / len) : 2.0f;
        ray->tfar = len > 2 * eps ? (float)(1 - eps / len) : 1.0f;
        ray->time = 0; ray->mask = 0xffffffffu; ray->id = 0; ray->flags = 0;
    }
    struct RTCRay *work = malloc((size_t)nrays * sizeof *work);

    /* Random pairs for the pair query (both orders of sampling included). */
    long npairs = nrays / 81;
    int *pi = malloc((size_t)npairs * sizeof *pi), *pj = malloc((size_t)npairs * sizeof *pj);
    for (long q = 0; q < npairs; q++) {
        pi[q] = (int)(rnd(&s) * m.nt);
        pj[q] = (int)(rnd(&s) * m.nt);
    }

    printf("# vis bench: %d triangles, %ld rays, epsilon %.3g, radkit rad_vis vs Embree rtcOccluded1\n",
           m.nt, nrays, eps);
    printf("method\tthreads\trays\tseconds\tMrays_per_s\trelative_to_embree\n");
    for (int threads = 1; threads <= 2; threads++) {
        omp_set_num_threads(threads);
        double embree_rate = 0;
        long embree_blocked = 0;
        for (int method = 0; method < 6; method++) {
            double best = 1e300;
            unsigned long long traced = 0;
            for (int rep = 0; rep < 3; rep++) {
                unsigned long long count = 0;
                long nb = 0;
                if (method == 0)
                    memcpy(work, rays, (size_t)nrays * sizeof *rays);
                double t0 = rad_sys_seconds();
                if (method == 0) {
#pragma omp parallel reduction(+ : nb)
                    {
                        struct RTCIntersectContext ctx;
                        rtcInitIntersectContext(&ctx);
#pragma omp for schedule(static)
                        for (long r = 0; r < nrays; r++) {
                            if (work[r].tnear > 1.0f)
                                continue;
                            rtcOccluded1(scene, &ctx, &work[r]);
                            nb += work[r].tfar < 0.0f;
                        }
                    }
                    count = (unsigned long long)nrays;
                    embree_blocked = nb;
                } else if (method <= 4) {
                    int packet = method == 1 ? 1 : method == 2 ? 4 : method == 3 ? 8 : 16;
                    rad_vis_params pp = par;
                    pp.packet = packet;
                    static rad_vis *pv;
                    if (rep == 0) {
                        rad_vis_destroy(pv);
                        pv = NULL;
                        rad_vis_create(m.xyz, (size_t)m.nv, m.tri, (size_t)m.nt, &pp, &pv);
                        t0 = rad_sys_seconds();
                    }
                    long chunk = 4096;
#pragma omp parallel for schedule(static) reduction(+ : count)
                    for (long c0 = 0; c0 < nrays; c0 += chunk) {
                        long n = c0 + chunk <= nrays ? chunk : nrays - c0;
                        rad_vis_stats st = {0, 0, 0};
                        rad_vis_occluded(pv, (size_t)n, from + 3 * c0, to + 3 * c0, blocked + c0, &st);
                        count += st.rays;
                    }
                    for (long r = 0; r < nrays; r++)
                        nb += blocked[r];
                    if (nb != embree_blocked)
                        fprintf(stderr, "vis_bench: packet %d finds %ld blocked, Embree %ld\n",
                                packet, nb, embree_blocked);
                } else {
#pragma omp parallel for schedule(dynamic, 64) reduction(+ : count)
                    for (long q = 0; q < npairs; q++) {
                        rad_vis_stats st = {0, 0, 0};
                        double f;
                        rad_vis_pair_fraction(vis, (size_t)pi[q], (size_t)pj[q], &f, &st);
                        count += st.rays;
                    }
                }
                double t = rad_sys_seconds() - t0;
                if (t < best)
                    best = t;
                traced = count;
            }
            double rate = (double)traced / best;
            if (method == 0)
                embree_rate = rate;
            const char *names[6] = {"embree_occluded1", "rad_vis_packet1", "rad_vis_packet4",
                                    "rad_vis_packet8", "rad_vis_packet16", "rad_vis_pairs"};
            printf("%s\t%d\t%llu\t%.4f\t%.3f\t%.3f\n", names[method], threads, traced, best,
                   rate / 1e6, rate / embree_rate);
            fflush(stdout);
        }
    }
    rtcReleaseScene(scene);
    rtcReleaseDevice(dev);
    rad_vis_destroy(vis);
    free(from); free(to); free(blocked); free(rays); free(work); free(pi); free(pj);
    free(m.xyz); free(m.tri);
    return 0;
}
