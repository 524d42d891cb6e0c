/* rad_solve: the pipeline from a loaded scene to per-face radiosities, for
 * every method (rad_solve.h).  One function per step: prepare (mesh, plan,
 * the plan's decisions applied to the parameters, per-face materials), then
 * one runner per method, then the per-face answer checked. */
#include "rad_solve.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rad_basis.h"
#include "rad_dense.h"
#include "rad_geom.h"
#include "rad_hierp.h"
#include "rad_io.h"
#include "rad_mesh.h"
#include "rad_sys.h"
#include "rad_vis.h"

rad_status rad_solve_method_parse(const char *text, rad_solve_method *out)
{
    static const char *const names[4] = {"dense", "hier", "mc", "cluster"};
    for (int m = 0; m < 4; m++)
        if (text && strcmp(text, names[m]) == 0) {
            *out = (rad_solve_method)m;
            return RAD_OK;
        }
    return RAD_ERROR(RAD_EINVAL, "solve: unknown method '%s' (expected dense, hier, cluster or "
                                 "mc)", text ? text : "");
}

const char *rad_solve_method_name(rad_solve_method m)
{
    return m == RAD_SOLVE_HIER      ? "hier"
           : m == RAD_SOLVE_CLUSTER ? "cluster"
           : m == RAD_SOLVE_MC      ? "mc"
                                    : "dense";
}

void rad_solve_params_default(rad_solve_params *p)
{
    memset(p, 0, sizeof *p);
    p->method = RAD_SOLVE_DENSE;
    rad_scene_effects_params_default(&p->effects);
    rad_radiosity_params_default(&p->assembly);
    rad_dense_params_default(&p->dense);
    p->dense_max_elements = 46340;
    rad_hier_params_default(&p->hier);
    p->hier.min_area = -1.0;
    rad_mc_params_default(&p->mc);
}

void rad_solution_destroy(rad_solution *s)
{
    if (!s)
        return;
    free(s->face_area);
    free(s->face_se);
    free(s->element_corners);
    free(s->element_face);
    free(s->element_coef);
    free(s->display_xyz);
    free(s->display_tri);
    free(s->display_material);
    free(s->display_E);
    free(s->display_B);
    free(s->display_corners);
    free(s);
}

/* What every method starts from: the scene's triangles as a mesh, the plan,
 * and per input triangle its reflectance and emission (faces x 3). */
typedef struct prepared {
    const rad_scene *scene;
    rad_mesh *mesh;
    int faces;
    double *rho, *E; /* one block of 6 faces */
    /* what hier meshes (pieces_make): the input triangles, or their pieces
       cut along contact lines, each naming its input triangle in parent
       (NULL when not cut), with their reflectance and emission */
    const double *xyz;
    size_t nv, nt;
    const int *tri, *parent;
    const double *prho, *pE;
    rad_mesh_contacts cut;
    double *cut_rho; /* one block of 6 pieces */
} prepared;

static void prepared_free(prepared *pr)
{
    rad_mesh_destroy(pr->mesh);
    free(pr->rho);
    rad_mesh_contacts_free(&pr->cut);
    free(pr->cut_rho);
}

/* With the plan's contact on, the triangles hier meshes become the pieces
 * of the plan's contact cut (prepare kept it, and set the input's). */
static rad_status pieces_make(prepared *pr, const rad_solution *s)
{
    if (!s->plan.contact.on)
        return RAD_OK;
    size_t n = pr->cut.nt, faces = (size_t)pr->faces;
    if (!(pr->cut_rho = malloc(n * 6 * sizeof *pr->cut_rho)))
        return RAD_ERROR(RAD_ENOMEM, "solve: no memory for %zu pieces", n);
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++) {
            size_t f = (size_t)pr->cut.parent[i];
            pr->cut_rho[i + c * n] = pr->rho[f + c * faces];
            pr->cut_rho[3 * n + i + c * n] = pr->E[f + c * faces];
        }
    pr->xyz = pr->cut.xyz;
    pr->nv = pr->cut.nv;
    pr->tri = pr->cut.tri;
    pr->nt = n;
    pr->parent = pr->cut.parent;
    pr->prho = pr->cut_rho;
    pr->pE = pr->cut_rho + 3 * n;
    return RAD_OK;
}

static void add_phase(rad_solution *s, const char *name, double seconds)
{
    if (s->nphases < RAD_SOLVE_MAX_PHASES)
        s->phases[s->nphases++] = (rad_solve_phase){name, seconds};
}

/* The plan's decisions, applied to the parameters in s->used. */
static rad_status apply_plan(rad_solution *s)
{
    const rad_effects_plan *plan = &s->plan;
    rad_solve_params *u = &s->used;
    if (plan->refusal[0])
        return RAD_ERROR(RAD_ENUMERIC, "solve: %s", plan->refusal);
    if (u->basis != 0 && u->method == RAD_SOLVE_MC)
        return RAD_ERROR(RAD_EINVAL, "solve: --basis p%d applies to --method dense and hier (the "
                                     "Monte Carlo method estimates per-face means)",
                         u->basis);
    if (u->emission && u->method != RAD_SOLVE_DENSE && !(u->method == RAD_SOLVE_HIER && u->basis > 0))
        return RAD_ERROR(RAD_EINVAL, "solve: an emission field applies to the dense method and "
                                     "to hier with p1 or p2 elements only");
    if (u->basis < 0 || u->basis > RAD_BASIS_MAX_ORDER)
        return RAD_ERROR(RAD_EINVAL, "solve: basis order %d is not 0, 1 or 2", u->basis);
    if (u->method == RAD_SOLVE_CLUSTER && u->basis != 0)
        return RAD_ERROR(RAD_EINVAL, "solve: --basis p%d applies to --method dense and hier; "
                                     "cluster has constant elements", u->basis);
    /* clustering: the plan decides for hier with constant elements, --method
       cluster asks for it, nothing else has a cluster layer */
    rad_effect_decision *cl = &s->plan.clustering;
    int acts = u->method == RAD_SOLVE_HIER && u->basis == 0;
    if (u->method == RAD_SOLVE_CLUSTER) {
        if (cl->forced && !cl->on)
            return RAD_ERROR(RAD_EINVAL, "solve: --clustering off contradicts --method cluster");
        cl->on = 1;
        snprintf(cl->reason, sizeof cl->reason, "--method cluster links through a cluster "
                 "hierarchy");
    } else if (!acts) {
        if (cl->forced && cl->on)
            return RAD_ERROR(RAD_EINVAL, "solve: --clustering on applies to --method hier with "
                                         "constant elements (or --method cluster)");
        cl->on = 0;
        snprintf(cl->reason, sizeof cl->reason, "%s has no cluster layer",
                 u->method == RAD_SOLVE_HIER ? "hier with p1/p2 elements"
                 : u->method == RAD_SOLVE_MC ? "Monte Carlo"
                                             : "dense radiosity");
    }
    u->hier.cluster = cl->on && (acts || u->method == RAD_SOLVE_CLUSTER);
    /* contact lines: hier and cluster cut their input triangles along them */
    rad_effect_decision *ct = &s->plan.contact;
    if (u->method == RAD_SOLVE_DENSE || u->method == RAD_SOLVE_MC) {
        if (ct->forced && ct->on)
            return RAD_ERROR(RAD_EINVAL, "solve: --contact on applies to --method hier and cluster");
        ct->on = 0;
        snprintf(ct->reason, sizeof ct->reason, "%s solves on the input triangles",
                 u->method == RAD_SOLVE_MC ? "Monte Carlo" : "dense radiosity");
    }
    if (u->method == RAD_SOLVE_MC) {
        if (plan->facing_away.forced || plan->singular.forced)
            return RAD_ERROR(RAD_EINVAL, "solve: --facing-away and --singular decide how form "
                                         "factors are integrated; --method mc computes none");
        u->mc.occlusion = plan->occlusion.on;
        return RAD_OK;
    }
    /* reflectance near 1: the defaults' tolerances tightened */
    if (!u->keep_tol)
        u->assembly.ff.tol *= plan->tighten;
    if (!u->keep_solver_tol)
        u->dense.tol *= plan->tighten;
    u->assembly.visible.tol *= plan->tighten;
    u->hier.tol *= plan->tighten;
    u->hier.bound_tol *= plan->tighten;
    /* facing-away pairs and singular pairs */
    u->assembly.ff.skip_facing_away = plan->facing_away.on;
    u->assembly.ff.singular_rules = plan->singular.on;
    u->hier.ff.singular_rules = plan->singular.on;
    u->hier.singular = plan->singular.on;
    if ((u->method == RAD_SOLVE_HIER || u->method == RAD_SOLVE_CLUSTER) && !plan->facing_away.on)
        return RAD_ERROR(RAD_EINVAL, "solve: --facing-away off applies to --method dense only "
                                     "(hier links only elements that face each other)");
    /* colour: channels that may share a system share one when off */
    u->dense.share_channels = !plan->colour.on;
    u->hier.sealed = plan->sealed;
    return RAD_OK;
}

static rad_status prepare(const rad_scene *scene, rad_solution *s, prepared *pr)
{
    memset(pr, 0, sizeof *pr);
    pr->scene = scene;
    pr->faces = rad_scene_triangle_count(scene);
    rad_status st = rad_mesh_create(rad_scene_vertices(scene), rad_scene_vertex_count(scene),
                                    rad_scene_triangles(scene), pr->faces, NULL, &pr->mesh);
    if (st == RAD_OK)
        st = rad_scene_effects_plan_cut(scene, pr->mesh, &s->used.effects, &s->plan, &pr->cut);
    if (st == RAD_OK)
        st = apply_plan(s);
    if (st != RAD_OK)
        return st;
    /* only hier and cluster mesh the pieces (pieces_make), and only when
       the plan cuts */
    if (!s->plan.contact.on || (s->method != RAD_SOLVE_HIER && s->method != RAD_SOLVE_CLUSTER))
        rad_mesh_contacts_free(&pr->cut);
    size_t n = (size_t)pr->faces;
    if (!(pr->rho = malloc(n * 6 * sizeof *pr->rho)))
        return RAD_ERROR(RAD_ENOMEM, "solve: no memory for %zu faces", n);
    pr->E = pr->rho + 3 * n;
    pr->xyz = rad_scene_vertices(scene);
    pr->nv = (size_t)rad_scene_vertex_count(scene);
    pr->tri = rad_scene_triangles(scene);
    pr->nt = n;
    pr->prho = pr->rho;
    pr->pE = pr->E;
    const int *tri_mat = rad_scene_triangle_materials(scene);
    const rad_scene_material *mats = rad_scene_materials(scene);
    for (size_t i = 0; i < n; i++) {
        const rad_scene_material *m = &mats[tri_mat[i]];
        /* colour off: one system, the channels' mean reflectance (exact when grey) */
        double grey = (m->rho[0] + m->rho[1] + m->rho[2]) / 3.0;
        for (int c = 0; c < 3; c++) {
            pr->rho[i + c * n] = s->plan.colour.on ? m->rho[c] : grey;
            pr->E[i + c * n] = m->emission[c];
        }
    }
    return RAD_OK;
}

/* An answer is a radiosity, finite and non-negative, or it is not returned.
 * The solvers check their own arithmetic; this catches what reaches the
 * answer by other ways (an emission near the largest double, overflow in a
 * path's weight). */
static rad_status check_answer(const char *method, size_t n, const double *B)
{
    static const char channel[3] = {'r', 'g', 'b'};
    for (int c = 0; c < 3; c++)
        for (size_t i = 0; i < n; i++) {
            double b = B[i + (size_t)c * n];
            if (!isfinite(b))
                return RAD_ERROR(RAD_ENUMERIC, "%s: face %zu has a non-finite radiosity (B_%c = %g): "
                                 "an emission or a scale beyond double precision's range?",
                                 method, i, channel[c], b);
            if (b < 0.0)
                return RAD_ERROR(RAD_ENUMERIC, "%s: face %zu has a negative radiosity (B_%c = %g)",
                                 method, i, channel[c], b);
        }
    return RAD_OK;
}

/* The per-face answer from per-element values (face_of, area, B: n x 3). */
static rad_status face_answer(rad_solution *s, size_t n, const int *face_of, const double *area,
                              const double *B)
{
    size_t faces = (size_t)s->faces;
    if (!(s->face_area = calloc(faces * 4, sizeof *s->face_area)))
        return RAD_ERROR(RAD_ENOMEM, "solve: no memory for %zu faces", faces);
    s->face_B = s->face_area + faces;
    rad_status st = rad_io_face_averages(n, face_of, area, B, faces, s->face_area, s->face_B);
    return st == RAD_OK ? check_answer(rad_solve_method_name(s->method), faces, s->face_B) : st;
}

/* Room for a display of nv vertices and nt triangles (corners with edges);
 * vertices and triangles already made (hier's conforming mesh) are kept. */
static rad_status display_alloc(rad_solution *s, size_t nv, size_t nt)
{
    s->display_nv = nv;
    s->display_nt = nt;
    if (!s->display_xyz)
        s->display_xyz = malloc(nv * 3 * sizeof *s->display_xyz);
    if (!s->display_tri)
        s->display_tri = malloc(nt * 3 * sizeof *s->display_tri);
    s->display_material = malloc(nt * sizeof *s->display_material);
    s->display_E = malloc(nt * 3 * sizeof *s->display_E);
    s->display_B = malloc(nt * 3 * sizeof *s->display_B);
    if (s->used.edges)
        s->display_corners = malloc(nt * 9 * sizeof *s->display_corners);
    if (!s->display_xyz || !s->display_tri || !s->display_material || !s->display_E ||
        !s->display_B || (s->used.edges && !s->display_corners))
        return RAD_ERROR(RAD_ENOMEM, "solve: no memory for %zu display triangles", nt);
    return RAD_OK;
}

/* The display of per-triangle values on the triangles themselves (dense's
 * elements, mc's faces): copies, so that the solution owns them. */
static rad_status display_triangles(rad_solution *s, size_t nv, const double *xyz, size_t nt,
                                    const int *tri, const int *material, const double *E,
                                    const double *B)
{
    rad_status st = display_alloc(s, nv, nt);
    if (st != RAD_OK)
        return st;
    memcpy(s->display_xyz, xyz, nv * 3 * sizeof *xyz);
    memcpy(s->display_tri, tri, nt * 3 * sizeof *tri);
    memcpy(s->display_material, material, nt * sizeof *material);
    memcpy(s->display_E, E, nt * 3 * sizeof *E);
    memcpy(s->display_B, B, nt * 3 * sizeof *B);
    if (s->display_corners)
        for (size_t i = 0; i < nt; i++)
            for (int v = 0; v < 3; v++)
                memcpy(s->display_corners + 9 * i + 3 * v, xyz + 3 * (size_t)tri[3 * i + v],
                       3 * sizeof *xyz);
    return RAD_OK;
}

/* Visibility over the input triangles, when the plan says something can
 * occlude: elements lie on their input triangles, which rad_vis ignores as
 * blockers of pairs on them. */
static rad_status make_vis(const prepared *pr, int needed, double eps_rel, int strata,
                           rad_vis **vis)
{
    *vis = NULL;
    if (!needed)
        return RAD_OK;
    rad_vis_params vp;
    rad_vis_params_default(&vp);
    if (eps_rel > 0.0)
        vp.eps_rel = eps_rel;
    if (strata > 0)
        vp.strata_per_edge = strata;
    return rad_vis_create(pr->xyz, pr->nv, pr->tri, pr->nt, &vp, vis);
}

/* ---- dense ---------------------------------------------------------------- */

/* The display of a polynomial solution: each element as a grid of 4^p
 * triangles (p the basis order) over its own (2^p + 1)(2^p + 2) / 2 points,
 * each triangle with the polynomial at its centroid: smooth shading shows
 * the polynomial within an element, and its jumps between elements. */
static rad_status display_basis(rad_solution *s, const int *material, const double *E)
{
    int order = s->used.basis, m = rad_basis_size(order), k = 1 << order;
    size_t n = s->elements, N = n * (size_t)m;
    size_t pts = (size_t)(k + 1) * (size_t)(k + 2) / 2, sub = (size_t)k * (size_t)k;
    size_t nv = n * pts, nt = n * sub;
    rad_status st = display_alloc(s, nv, nt);
    if (st != RAD_OK)
        return st;
    for (size_t e = 0; e < n; e++) {
        const double *c = s->element_corners + 9 * e;
        rad_vec3 t[3] = {{c[0], c[1], c[2]}, {c[3], c[4], c[5]}, {c[6], c[7], c[8]}};
        double area = rad_geom_triangle_area(t[0], t[1], t[2]);
        /* grid point (a, b), a + b <= k, at local (a / k, b / k) */
        size_t base = e * pts, v = 0;
        for (int b = 0; b <= k; b++)
            for (int a = 0; a + b <= k; a++, v++) {
                rad_vec3 x = rad_geom_triangle_point(t[0], t[1], t[2], (double)a / k, (double)b / k);
                double *o = s->display_xyz + 3 * (base + v);
                o[0] = x.x;
                o[1] = x.y;
                o[2] = x.z;
            }
        size_t f = e * sub;
        for (int b = 0; b < k; b++)
            for (int a = 0; a + b < k; a++) {
                /* index of grid point (a, b): rows of k + 1, k, ... points */
#define GRID(A, B) (base + (size_t)((B) * (k + 1) - (B) * ((B) - 1) / 2 + (A)))
                int up[3] = {(int)GRID(a, b), (int)GRID(a + 1, b), (int)GRID(a, b + 1)};
                int down[3] = {(int)GRID(a + 1, b), (int)GRID(a + 1, b + 1), (int)GRID(a, b + 1)};
#undef GRID
                for (int w = 0; w < 2; w++) {
                    if (w == 1 && a + b + 1 >= k)
                        break;
                    const int *q = w ? down : up;
                    double cs = w ? (a + 2.0 / 3.0) / k : (a + 1.0 / 3.0) / k;
                    double ct = w ? (b + 2.0 / 3.0) / k : (b + 1.0 / 3.0) / k;
                    memcpy(s->display_tri + 3 * f, q, 3 * sizeof *q);
                    s->display_material[f] = material[e];
                    for (int ch = 0; ch < 3; ch++) {
                        s->display_E[f + ch * nt] = E[e + ch * n];
                        s->display_B[f + ch * nt] = rad_basis_value(
                            order, area, s->element_coef + e * (size_t)m + ch * N, cs, ct);
                    }
                    if (s->display_corners)
                        memcpy(s->display_corners + 9 * f, c, 9 * sizeof *c);
                    f++;
                }
            }
    }
    return RAD_OK;
}

/* The elements' corners and input faces, for callers that evaluate the
 * solution's polynomials (element_coef). */
static rad_status element_arrays(rad_solution *s, const rad_mesh *mesh)
{
    size_t n = (size_t)rad_mesh_face_count(mesh);
    s->element_corners = malloc(n * 9 * sizeof *s->element_corners);
    s->element_face = malloc(n * sizeof *s->element_face);
    if (!s->element_corners || !s->element_face)
        return RAD_ERROR(RAD_ENOMEM, "solve: no memory for %zu elements", n);
    const double *xyz = rad_mesh_vertices(mesh);
    const int *tri = rad_mesh_triangles(mesh);
    for (size_t i = 0; i < n; i++)
        for (int v = 0; v < 3; v++)
            memcpy(s->element_corners + 9 * i + 3 * v, xyz + 3 * (size_t)tri[3 * i + (size_t)v],
                   3 * sizeof *xyz);
    memcpy(s->element_face, rad_mesh_input_faces(mesh), n * sizeof *s->element_face);
    return RAD_OK;
}

/* The emission field of face f, channel c, as rad_basis_project takes it. */
typedef struct emission_at {
    const rad_solve_params *u;
    int face, channel;
} emission_at;

static double emission_value(rad_vec3 x, void *ctx)
{
    const emission_at *e = ctx;
    return e->u->emission(e->face, x, e->channel, e->u->emission_ctx);
}

/* Dense in a polynomial basis: the couplings K of the orthonormal functions
 * (rad_radiosity_assemble_basis, from the P0 couplings G), the system
 * b = e + rho K b for the coefficients (e: the emission's projection, E
 * sqrt(A) on each constant, or the field's), and per element B = b_0 /
 * sqrt(A), its mean; the coefficients stay in the solution. */
static rad_status basis_solve(rad_solution *s, const rad_mesh *mesh, const rad_vis *vis,
                              const double *G, const double *areas, const double *rho, double *E,
                              double *B, double t_vis)
{
    rad_solve_params *u = &s->used;
    int n = rad_mesh_face_count(mesh), m = rad_basis_size(u->basis);
    size_t nn = (size_t)n, N = nn * (size_t)m;
    if (N > u->dense_max_elements)
        return RAD_ERROR(RAD_ETOOBIG, "solve: basis p%d on %d elements makes %zu unknowns, "
                                      "beyond what a dense solve can hold; use fewer elements",
                         u->basis, n, N);
    rad_status st = rad_dense_radiosity_check_size(N, u->dense.method);
    if (st != RAD_OK)
        return st;
    double *K = malloc(N * N * sizeof *K), *work = malloc(N * 7 * sizeof *work);
    s->element_coef = malloc(N * 3 * sizeof *s->element_coef);
    if (!K || !work || !s->element_coef) {
        free(K);
        free(work);
        return RAD_ERROR(RAD_ENOMEM, "solve: no memory for the %zu x %zu basis couplings", N, N);
    }
    double *one = work, *rN = work + N, *eN = work + 4 * N, *bN = s->element_coef;
    const double *xyz = rad_mesh_vertices(mesh);
    const int *tri = rad_mesh_triangles(mesh), *parent = rad_mesh_input_faces(mesh);
    for (size_t i = 0; i < nn && st == RAD_OK; i++) {
        for (size_t k = 0; k < (size_t)m; k++) {
            size_t I = i * (size_t)m + k;
            one[I] = 1.0;
            for (int c = 0; c < 3; c++) {
                rN[I + c * N] = rho[i + c * nn];
                eN[I + c * N] = k == 0 ? E[i + c * nn] * sqrt(areas[i]) : 0.0;
            }
        }
        if (!u->emission)
            continue;
        rad_vec3 t[3];
        for (int v = 0; v < 3; v++) {
            const double *q = xyz + 3 * (size_t)tri[3 * i + (size_t)v];
            t[v] = rad_vec3_make(q[0], q[1], q[2]);
        }
        for (int c = 0; c < 3 && st == RAD_OK; c++) {
            emission_at at = {u, parent[i], c};
            double coef[RAD_BASIS_MAX_SIZE];
            st = rad_basis_project(u->basis, t, emission_value, &at, 2 * u->basis + 6, coef);
            for (int k = 0; k < m; k++)
                eN[i * (size_t)m + (size_t)k + c * N] = coef[k];
            E[i + c * nn] = coef[0] / sqrt(areas[i]);
            if (st == RAD_OK && !(E[i + c * nn] >= 0.0 && isfinite(E[i + c * nn])))
                st = RAD_ERROR(RAD_EINPUT, "solve: the emission field's mean on element %zu "
                                           "(face %d) is %g: not a finite exitance >= 0",
                               i, parent[i], E[i + c * nn]);
        }
    }
    if (st == RAD_OK)
        st = rad_radiosity_assemble_basis(xyz, tri, n, vis, &u->assembly, u->basis, G, areas, K,
                                          &s->assembly);
    double t_assembled = rad_sys_seconds();
    add_phase(s, "assemble", t_assembled - t_vis);
    if (st == RAD_OK) {
        rad_dense_params dp = u->dense;
        dp.signed_couplings = 1;
        st = rad_dense_radiosity_solve((int)N, K, one, rN, eN, bN, &dp, &s->dense);
    }
    add_phase(s, "solve", rad_sys_seconds() - t_assembled);
    if (st == RAD_OK)
        for (size_t i = 0; i < nn; i++)
            for (int c = 0; c < 3; c++)
                B[i + c * nn] = bN[i * (size_t)m + c * N] / sqrt(areas[i]);
    free(K);
    free(work);
    return st;
}

static rad_status run_dense(rad_solution *s, prepared *pr, double t_start)
{
    rad_solve_params *u = &s->used;
    rad_mesh *refined = NULL;
    rad_vis *vis = NULL;
    double *G = NULL, *work = NULL;
    int *material = NULL;
    rad_status st = RAD_OK;
    const rad_mesh *mesh = pr->mesh;
    if (u->refine > 0) {
        if ((st = rad_mesh_refine_uniform(pr->mesh, u->refine, u->dense_max_elements, &refined)) !=
            RAD_OK) {
            if (st == RAD_ETOOBIG)
                st = RAD_ERROR(RAD_ETOOBIG, "solve: --refine %d makes %.0f elements, beyond what a "
                                            "dense solve can hold; use fewer levels or --method hier",
                               u->refine, (double)pr->faces * pow(4.0, u->refine));
            return st;
        }
        mesh = refined;
    }
    int n = rad_mesh_face_count(mesh);
    size_t nn = (size_t)n;
    if ((st = rad_dense_radiosity_check_size(nn, u->dense.method)) != RAD_OK)
        goto done;
    const int *parent = rad_mesh_input_faces(mesh);
    size_t faces = (size_t)pr->faces;
    work = malloc(nn * 10 * sizeof *work);
    material = malloc(nn * sizeof *material);
    if (!work || !material) {
        st = RAD_ERROR(RAD_ENOMEM, "solve: no memory for %d elements", n);
        goto done;
    }
    double *rho = work, *E = work + 3 * nn, *B = work + 6 * nn, *areas = work + 9 * nn;
    const int *tri_mat = rad_scene_triangle_materials(pr->scene);
    for (size_t i = 0; i < nn; i++) {
        size_t f = (size_t)parent[i];
        material[i] = tri_mat[f];
        for (int c = 0; c < 3; c++) {
            rho[i + c * nn] = pr->rho[f + c * faces];
            E[i + c * nn] = pr->E[f + c * faces];
        }
    }
    double t_setup = rad_sys_seconds();
    add_phase(s, "setup", t_setup - t_start);
    if ((st = make_vis(pr, s->plan.occlusion.on, 0.0, u->assembly.visible.sample_strata, &vis)) !=
        RAD_OK)
        goto done;
    double t_vis = rad_sys_seconds();
    add_phase(s, "visibility", t_vis - t_setup);
    if (!(G = malloc(nn * nn * sizeof *G))) {
        st = RAD_ERROR(RAD_ENOMEM, "solve: no memory for the %d x %d coupling matrix", n, n);
        goto done;
    }
    u->assembly.face_of = parent;
    u->assembly.threads = u->threads;
    st = rad_radiosity_assemble(rad_mesh_vertices(mesh), rad_mesh_triangles(mesh), n, vis,
                                &u->assembly, G, areas, &s->assembly);
    if (st != RAD_OK)
        goto done;
    if (s->plan.sealed)
        s->assembly.rows_closed = rad_radiosity_close_rows(G, areas, n);
    if (u->basis > 0 || u->emission) {
        if ((st = basis_solve(s, mesh, vis, G, areas, rho, E, B, t_vis)) != RAD_OK)
            goto done;
    } else {
        double t_assembled = rad_sys_seconds();
        add_phase(s, "assemble", t_assembled - t_vis);
        if ((st = rad_dense_radiosity_solve(n, G, areas, rho, E, B, &u->dense, &s->dense)) !=
            RAD_OK)
            goto done;
        add_phase(s, "solve", rad_sys_seconds() - t_assembled);
    }
    u->assembly.face_of = NULL; /* borrowed from the mesh, freed below */
    if ((st = element_arrays(s, mesh)) != RAD_OK)
        goto done;
    s->elements = nn;
    s->links = s->assembly.pairs - s->assembly.pairs_not_facing;
    s->rays = s->assembly.rays;
    s->kernel_evals = s->assembly.kernel_evals;
    s->solver_name = rad_dense_method_name(s->dense.method);
    s->solver_iterations = s->dense.iterations;
    s->solver_residual = s->dense.residual;
    s->systems = s->dense.factorizations > 0 ? s->dense.factorizations : 3;
    if ((st = face_answer(s, nn, parent, areas, B)) != RAD_OK)
        goto done;
    if (u->display && s->element_coef && u->basis > 0)
        st = display_basis(s, material, E);
    else if (u->display)
        st = display_triangles(s, (size_t)rad_mesh_vertex_count(mesh), rad_mesh_vertices(mesh), nn,
                               rad_mesh_triangles(mesh), material, E, B);
done:
    u->assembly.face_of = NULL;
    free(G);
    free(work);
    free(material);
    rad_vis_destroy(vis);
    rad_mesh_destroy(refined);
    return st;
}

/* ---- hier ----------------------------------------------------------------- */

/* The leaves' conforming mesh as the display (T-vertices resolved, so that
 * vertex colours are smooth); each display triangle keeps its leaf's corners. */
static rad_status hier_display(rad_solution *s, const rad_hier *h, const prepared *pr, size_t n,
                               const int *leaf_face, const double *leaf_B)
{
    double *corners = malloc(n * 9 * sizeof *corners);
    if (!corners)
        return RAD_ERROR(RAD_ENOMEM, "solve: no memory for %zu leaves", n);
    rad_hier_leaves(h, NULL, NULL, corners, NULL);
    size_t nv = 0, nt = 0;
    int *leaf = NULL;
    rad_status st = rad_mesh_conform_leaves(corners, n, &s->display_xyz, &nv, &s->display_tri,
                                            &leaf, &nt);
    if (st != RAD_OK) {
        free(corners);
        return st;
    }
    if ((st = display_alloc(s, nv, nt)) != RAD_OK) {
        free(corners);
        free(leaf);
        return st;
    }
    const int *tri_mat = rad_scene_triangle_materials(pr->scene);
    size_t faces = (size_t)pr->faces;
    for (size_t t = 0; t < nt; t++) {
        size_t l = (size_t)leaf[t];
        size_t f = (size_t)leaf_face[l];
        s->display_material[t] = tri_mat[f];
        if (s->display_corners)
            memcpy(s->display_corners + 9 * t, corners + 9 * l, 9 * sizeof *corners);
        for (int c = 0; c < 3; c++) {
            s->display_E[t + c * nt] = pr->E[f + c * faces];
            s->display_B[t + c * nt] = leaf_B[l + c * n];
        }
    }
    free(corners);
    free(leaf);
    return RAD_OK;
}

/* The phases and work figures of a hierarchical solve (s->hier, from
 * rad_hier or rad_hierp): one set of '#' lines for both. */
static void hier_figures(rad_solution *s)
{
    add_phase(s, "link", s->hier.time_link_s);
    add_phase(s, "refine", s->hier.time_refine_s);
    add_phase(s, "solve", s->hier.time_solve_s);
    /* shared among processes: the exchanges, a part of the three phases above */
    if (s->used.hier.exchange.size > 1)
        add_phase(s, "comm", s->hier.time_comm_s);
    s->elements = s->hier.elements;
    s->links = (long long)s->hier.links;
    s->rays = s->hier.rays;
    s->kernel_evals = s->hier.kernel_evals;
    s->solver_name = s->used.hier.anderson > 0 && s->used.basis == 0 ? "anderson-push-pull"
                                                                      : "jacobi-push-pull";
    s->solver_iterations = s->hier.iterations;
    s->solver_residual = s->hier.residual;
    s->systems = 3;
}

/* The emission field at a point of one of the solver's triangles: the
 * field of the input face that holds the triangle (parent). */
typedef struct hierp_field {
    const rad_solve_params *u;
    const int *parent;
} hierp_field;

static double hierp_field_value(int face, rad_vec3 x, int channel, void *ctx)
{
    const hierp_field *f = ctx;
    return f->u->emission(f->parent ? f->parent[face] : face, x, channel, f->u->emission_ctx);
}

/* hier with polynomial elements (rad_hierp): the leaves' coefficients are
 * the solution's elements, shown as dense's are. */
static rad_status run_hierp(rad_solution *s, prepared *pr, const rad_vis *vis)
{
    rad_solve_params *u = &s->used;
    rad_hierp *h = NULL;
    int *material = NULL;
    double *leaf = NULL, *E = NULL;
    hierp_field field = {u, pr->parent};
    rad_status st = rad_hierp_create(pr->xyz, pr->nv, pr->tri, pr->nt, pr->prho, pr->pE, vis,
                                     &u->hier, u->basis, &h);
    if (st == RAD_OK && u->emission)
        st = rad_hierp_set_emission(h, hierp_field_value, &field);
    if (st == RAD_OK)
        st = rad_hierp_solve(h);
    if (st != RAD_OK)
        goto done;
    rad_hierp_get_stats(h, &s->hier);
    hier_figures(s);
    size_t n = rad_hierp_leaf_count(h), m = (size_t)rad_basis_size(u->basis);
    leaf = malloc(n * 4 * sizeof *leaf);
    E = malloc(n * 3 * sizeof *E);
    material = malloc(n * sizeof *material);
    s->element_corners = malloc(n * 9 * sizeof *s->element_corners);
    s->element_face = malloc(n * sizeof *s->element_face);
    s->element_coef = malloc(n * m * 3 * sizeof *s->element_coef);
    if (!leaf || !E || !material || !s->element_corners || !s->element_face ||
        !s->element_coef) {
        st = RAD_ERROR(RAD_ENOMEM, "solve: no memory for %zu elements", n);
        goto done;
    }
    double *area = leaf, *B = leaf + n;
    rad_hierp_leaves(h, s->element_face, area, s->element_corners, B, s->element_coef);
    if (pr->parent)
        for (size_t i = 0; i < n; i++)
            s->element_face[i] = pr->parent[s->element_face[i]];
    const int *tri_mat = rad_scene_triangle_materials(pr->scene);
    size_t faces = (size_t)pr->faces;
    for (size_t i = 0; i < n; i++) {
        size_t f = (size_t)s->element_face[i];
        material[i] = tri_mat[f];
        for (int c = 0; c < 3; c++)
            E[i + c * n] = pr->E[f + c * faces];
    }
    if ((st = face_answer(s, n, s->element_face, area, B)) == RAD_OK && u->display)
        st = display_basis(s, material, E);
done:
    free(leaf);
    free(E);
    free(material);
    rad_hierp_destroy(h);
    return st;
}

static rad_status run_hier(rad_solution *s, prepared *pr, double t_start)
{
    rad_solve_params *u = &s->used;
    if (u->hier.min_area < 0.0) {
        rad_scene_summary sum;
        rad_scene_summarize(pr->scene, &sum);
        u->hier.min_area =
            sum.total_area * fmin(1e-4, fmax(1e-10, 1e-2 * u->hier.eps * u->hier.eps));
    }
    u->hier.threads = u->threads;
    double t_setup = rad_sys_seconds();
    add_phase(s, "setup", t_setup - t_start);
    rad_vis *vis = NULL;
    rad_hier *h = NULL;
    double *leaf = NULL;
    int *leaf_face = NULL;
    rad_status st = pieces_make(pr, s);
    if (st == RAD_OK)
        st = make_vis(pr, s->plan.occlusion.on, 0.0, 0, &vis);
    if (st != RAD_OK)
        return st;
    add_phase(s, "visibility", rad_sys_seconds() - t_setup);
    if (u->basis > 0) {
        st = run_hierp(s, pr, vis);
        rad_vis_destroy(vis);
        return st;
    }
    st = rad_hier_create(pr->xyz, pr->nv, pr->tri, pr->nt, pr->prho, pr->pE, vis, &u->hier, &h);
    if (st == RAD_OK)
        st = rad_hier_solve(h);
    if (st != RAD_OK)
        goto done;
    rad_hier_get_stats(h, &s->hier);
    hier_figures(s);
    size_t n = rad_hier_leaf_count(h);
    /* zeroed: the compiler cannot see that rad_hier_leaves writes them all */
    leaf = calloc(n * 4, sizeof *leaf);
    leaf_face = calloc(n, sizeof *leaf_face);
    if (!leaf || !leaf_face) {
        st = RAD_ERROR(RAD_ENOMEM, "solve: no memory for %zu elements", n);
        goto done;
    }
    double *area = leaf, *B = leaf + n;
    rad_hier_leaves(h, leaf_face, area, NULL, B);
    if (pr->parent)
        for (size_t i = 0; i < n; i++)
            leaf_face[i] = pr->parent[leaf_face[i]];
    if ((st = face_answer(s, n, leaf_face, area, B)) == RAD_OK && u->display)
        st = hier_display(s, h, pr, n, leaf_face, B);
done:
    free(leaf);
    free(leaf_face);
    rad_hier_destroy(h);
    rad_vis_destroy(vis);
    return st;
}

/* ---- mc ------------------------------------------------------------------- */

/* The standard error in the measure the studies use: area-weighted standard
 * error over the area-weighted mean reflected radiosity (B - E), three
 * channels summed; and the largest face's on the same scale. */
static void relative_errors(size_t n, const double *area, const double *B, const double *E,
                            const double *se, double *l1, double *worst)
{
    double num = 0.0, den = 0.0, total = 0.0, top = 0.0;
    for (size_t i = 0; i < n; i++) {
        total += area[i];
        for (int c = 0; c < 3; c++) {
            num += area[i] * se[i + c * n];
            den += area[i] * (B[i + c * n] - E[i + c * n]);
            top = rad_dmax(top, se[i + c * n]);
        }
    }
    *l1 = den > 0.0 ? num / den : 0.0;
    *worst = den > 0.0 ? top / (den / (3.0 * total)) : 0.0;
}

static rad_status run_mc(rad_solution *s, prepared *pr, double t_start)
{
    rad_solve_params *u = &s->used;
    size_t n = (size_t)pr->faces, nv = (size_t)rad_scene_vertex_count(pr->scene);
    const double *xyz = rad_scene_vertices(pr->scene);
    const int *tri = rad_scene_triangles(pr->scene);
    s->face_area = malloc(n * 4 * sizeof *s->face_area);
    s->face_se = malloc(n * 3 * sizeof *s->face_se);
    if (!s->face_area || !s->face_se)
        return RAD_ERROR(RAD_ENOMEM, "solve: no memory for %zu faces", n);
    s->face_B = s->face_area + n;
    for (size_t i = 0; i < n; i++) {
        const double *a = xyz + 3 * (size_t)tri[3 * i], *b = xyz + 3 * (size_t)tri[3 * i + 1],
                     *c = xyz + 3 * (size_t)tri[3 * i + 2];
        s->face_area[i] = rad_geom_triangle_area(rad_vec3_make(a[0], a[1], a[2]),
                                                 rad_vec3_make(b[0], b[1], b[2]),
                                                 rad_vec3_make(c[0], c[1], c[2]));
    }
    double t_setup = rad_sys_seconds();
    add_phase(s, "setup", t_setup - t_start);
    /* Paths need closest hits in every scene (the plan decides only whether
     * shadow rays are needed).  A small ray epsilon: hits on a path vertex's
     * own triangle are rejected by id, the epsilon only guards the far end. */
    rad_vis *vis = NULL;
    rad_status st = make_vis(pr, 1, 1e-6, 0, &vis);
    if (st != RAD_OK)
        return st;
    double t_vis = rad_sys_seconds();
    add_phase(s, "visibility", t_vis - t_setup);
    u->mc.threads = u->threads;
    st = rad_mc_solve(xyz, nv, tri, n, pr->rho, pr->E, vis, &u->mc, s->face_B, s->face_se, &s->mc);
    rad_vis_destroy(vis);
    if (st != RAD_OK || (st = check_answer("mc", n, s->face_B)) != RAD_OK)
        return st;
    add_phase(s, "paths", rad_sys_seconds() - t_vis);
    relative_errors(n, s->face_area, s->face_B, pr->E, s->face_se, &s->se_rel_l1, &s->se_rel_max);
    s->elements = n;
    s->rays = (unsigned long long)s->mc.rays;
    s->solver_name = "path-tracing";
    s->solver_iterations = s->mc.paths;
    s->solver_residual = s->se_rel_l1;
    if (u->display)
        st = display_triangles(s, nv, xyz, n, tri, rad_scene_triangle_materials(pr->scene), pr->E,
                               s->face_B);
    return st;
}

rad_status rad_solve_run(const rad_scene *scene, const rad_solve_params *params,
                         rad_solution **out)
{
    if (out)
        *out = NULL;
    if (!scene || !out)
        return RAD_ERROR(RAD_EINVAL, "rad_solve_run: NULL argument");
    double t_start = rad_sys_seconds();
    rad_solution *s = calloc(1, sizeof *s);
    if (!s)
        return RAD_ERROR(RAD_ENOMEM, "solve: no memory");
    if (params)
        s->used = *params;
    else
        rad_solve_params_default(&s->used);
    s->method = s->used.method;
    s->faces = rad_scene_triangle_count(scene);
    s->used.effects.threads = s->used.threads;
    prepared pr;
    rad_status st = prepare(scene, s, &pr);
    if (st == RAD_OK) {
        if (s->method == RAD_SOLVE_HIER || s->method == RAD_SOLVE_CLUSTER)
            st = run_hier(s, &pr, t_start);
        else if (s->method == RAD_SOLVE_MC)
            st = run_mc(s, &pr, t_start);
        else
            st = run_dense(s, &pr, t_start);
    }
    prepared_free(&pr);
    s->total_seconds = rad_sys_seconds() - t_start;
    if (st != RAD_OK) {
        rad_solution_destroy(s);
        return st;
    }
    *out = s;
    return RAD_OK;
}
