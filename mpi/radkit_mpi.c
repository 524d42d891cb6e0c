/* radkit-mpi: dense Galerkin radiosity over MPI ranks with ScaLAPACK (issue
 * 18, dense part); `--method hier|cluster` goes to hier_mpi.c.  Built only by
 * `make mpi`; the plain build and `make test` never need MPI.
 *
 *   mpirun -np 4 build/radkit-mpi solve SCENE [--refine K] [--rule R] [--tol T]
 *                [--block NB] [--out FILE] [--quiet] [scene options]
 *
 * Every rank loads the scene, refines it, decides the effects plan and builds
 * visibility (replicated: small next to the matrix).  The ranks form a
 * near-square BLACS grid; the matrix K = I - diag(rho / A) G is distributed
 * block-cyclically (blocks NB x NB, default 64) and each rank computes only
 * the couplings of its own blocks (rad_radiosity_pair, the serial assembly's
 * own function, so every entry is bit for bit the serial one), only the
 * lower triangle: each pair once.  pdposv solves the symmetric form
 * S = diag(A / rho) - G (as radkit solve --solver cholesky) for each group of
 * channels sharing a reflectance; the solution is summed onto
 * every rank (MPI_Allreduce), and rank 0 prints the same table as
 * `radkit solve` (solve_table.c) with `# ranks` and the largest rank's peak
 * memory.  Memory per rank: about 8 n^2 / ranks bytes for the matrix, twice
 * that with G kept for the residual. */
#include <math.h>
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "rad_dense.h"
#include "rad_ff.h"
#include "rad_geom.h"
#include "rad_io.h"
#include "rad_mesh.h"
#include "rad_radiosity.h"
#include "rad_scene.h"
#include "rad_solve.h"
#include "rad_sys.h"
#include "rad_vis.h"
#include "radkit_mpi.h"
#include "solve.h"

/* ScaLAPACK and BLACS (Fortran and C entry points of libscalapack-openmpi) */
void Cblacs_pinfo(int *me, int *np);
void Cblacs_get(int ctx, int what, int *val);
void Cblacs_gridinit(int *ctx, const char *order, int nprow, int npcol);
void Cblacs_gridinfo(int ctx, int *nprow, int *npcol, int *myrow, int *mycol);
void Cblacs_gridexit(int ctx);
int numroc_(const int *n, const int *nb, const int *iproc, const int *isrc, const int *nprocs);
void descinit_(int *desc, const int *m, const int *n, const int *mb, const int *nb,
               const int *irsrc, const int *icsrc, const int *ctx, const int *lld, int *info);
void pdposv_(const char *uplo, const int *n, const int *nrhs, double *a, const int *ia,
             const int *ja, const int *desca, double *b, const int *ib, const int *jb,
             const int *descb, int *info);

static const char help[] =
    "usage: mpirun -np N radkit-mpi solve SCENE [--method dense] [--refine K] [--rule RULE]\n"
    "                    [--tol T] [--block NB] [--out FILE] [--stats FILE] [--quiet]\n"
    "                    [scene options]\n"
    "       mpirun -np N radkit-mpi solve SCENE --method hier|cluster [--gather G] ...\n"
    "                    (radkit-mpi solve --method hier --help)\n"
    "\n"
    "Dense Galerkin radiosity (as radkit solve --method dense --solver cholesky)\n"
    "with the coupling matrix distributed block-cyclically over the MPI ranks and\n"
    "solved by ScaLAPACK's pdposv; each rank computes only the lower triangle of\n"
    "its own blocks, each pair once.  The table is\n"
    "radkit solve's, with '# ranks' and '# memory_peak_bytes_per_rank' (the\n"
    "largest rank's).\n"
    "\n"
    "  --block NB       the block size of the distribution (default 64)\n"
    "  --stats FILE     radkit solve's JSON with top-level ranks and\n"
    "                   memory_peak_bytes_per_rank\n";

/* global index of local index l in a block-cyclic dimension */
static int global_index(int l, int nb, int p, int np) { return (l / nb) * np * nb + p * nb + l % nb; }

typedef struct mpi_opts {
    solve_options o;
    const char *block;
} mpi_opts;

/* st on this rank, or a failure on any other: every rank takes the same
 * branch, so none waits in a collective the others have left. */
static rad_status agree(rad_status st)
{
    int mine = st != RAD_OK, any = 0;
    MPI_Allreduce(&mine, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    if (st == RAD_OK && any)
        return RAD_ERROR(RAD_ENUMERIC, "solve: another rank failed");
    return st;
}

static int fail(int rank, rad_status st)
{
    if (rank == 0)
        return cli_fail(st);
    return rad_status_exit_code(st);
}

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    int rank = 0, ranks = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &ranks);
    int code = 0;
    mpi_opts m;
    memset(&m, 0, sizeof m);
    solve_options *o = &m.o;
    cli_scene_options_init(&o->scene_opts);
    const char *method_opt = NULL;
    enum { OWN = 11 };
    cli_option table[OWN + CLI_SCENE_OPTION_COUNT + 1] = {
        {"", &o->scene, NULL, "scene"},      {"--refine", &o->refine, NULL, NULL},
        {"--rule", &o->rule, NULL, NULL},    {"--tol", &o->tol, NULL, NULL},
        {"--block", &m.block, NULL, NULL},   {"--out", &o->out, NULL, NULL},
        {"--quiet", NULL, &o->quiet, NULL},  {"--help", NULL, &o->help, NULL},
        {"-h", NULL, &o->help, NULL},        {"--stats", &o->stats, NULL, NULL},
        {"--method", &method_opt, NULL, NULL},
    };
    int nopt = OWN + cli_scene_options_add(&o->scene_opts, table + OWN);
    table[nopt] = (cli_option){NULL, NULL, NULL, NULL};
    rad_status st = RAD_OK;
    if (argc < 2 || strcmp(argv[1], "solve") != 0) {
        if (rank == 0)
            fputs(help, stderr);
        MPI_Finalize();
        return 2;
    }
    /* hier and cluster take radkit solve's own options (hier_mpi.c) */
    const char *method = NULL;
    for (int i = 2; i < argc; i++) {
        if (strncmp(argv[i], "--method=", 9) == 0)
            method = argv[i] + 9;
        else if (strcmp(argv[i], "--method") == 0 && i + 1 < argc)
            method = argv[++i];
    }
    if (method && (strcmp(method, "hier") == 0 || strcmp(method, "cluster") == 0)) {
        code = radkit_mpi_hier(argc, argv, rank, ranks);
        MPI_Finalize();
        return code;
    }
    if ((st = cli_parse("solve", argc, argv, 2, table)) != RAD_OK) {
        code = fail(rank, st);
        MPI_Finalize();
        return code;
    }
    if (o->help) {
        if (rank == 0)
            fputs(help, stdout);
        MPI_Finalize();
        return 0;
    }
    double t_start = rad_sys_seconds();
    rad_scene_params sp;
    rad_effects_params ep;
    rad_scene_params_default(&sp);
    rad_scene_effects_params_default(&ep);
    rad_solve_params p;
    int nb = 64;
    rad_scene *scene = NULL;
    rad_mesh *base = NULL, *mesh = NULL;
    rad_vis *vis = NULL;
    rad_solution sol;
    memset(&sol, 0, sizeof sol);
    double *work = NULL, *Gloc = NULL, *Kloc = NULL, *Bloc = NULL, *x = NULL;
    if (!o->scene)
        st = RAD_ERROR(RAD_EINVAL, "solve: no scene given");
    if (st == RAD_OK && method_opt && strcmp(method_opt, "dense") != 0)
        st = RAD_ERROR(RAD_EINVAL, "solve: radkit-mpi runs --method dense, hier or cluster, not "
                                   "'%s'", method_opt);
    if (st == RAD_OK)
        st = cli_scene_options_apply("solve", &o->scene_opts, &sp, &ep);
    if (st == RAD_OK)
        st = solve_parse_params(o, &ep, &p);
    if (st == RAD_OK && m.block)
        st = cli_parse_positive_int("solve: --block", m.block, 4096, &nb);
    if (st == RAD_OK && !o->scene)
        st = RAD_ERROR(RAD_EINVAL, "solve: no scene given");
    if (st == RAD_OK)
        st = rad_scene_load(o->scene, &sp, &scene);
    int faces = scene ? rad_scene_triangle_count(scene) : 0;
    if (st == RAD_OK)
        st = rad_mesh_create(rad_scene_vertices(scene), rad_scene_vertex_count(scene),
                             rad_scene_triangles(scene), faces, NULL, &base);
    if (st == RAD_OK)
        st = rad_scene_effects_plan(scene, base, &ep, &sol.plan);
    if (st == RAD_OK && sol.plan.refusal[0])
        st = RAD_ERROR(RAD_ENUMERIC, "solve: %s", sol.plan.refusal);
    if (st == RAD_OK && p.refine > 0)
        st = rad_mesh_refine_uniform(base, p.refine, (size_t)1 << 30, &mesh);
    /* the same input on every rank: every rank fails alike here */
    if (st != RAD_OK)
        goto done;
    if (!mesh) {
        mesh = base;
        base = NULL;
    }
    /* the plan's decisions, as rad_solve applies them to dense */
    if (!p.keep_tol)
        p.assembly.ff.tol *= sol.plan.tighten;
    p.assembly.visible.tol *= sol.plan.tighten;
    p.assembly.ff.skip_facing_away = sol.plan.facing_away.on;
    p.assembly.ff.singular_rules = sol.plan.singular.on;
    int n = rad_mesh_face_count(mesh);
    size_t nn = (size_t)n;
    const double *xyz = rad_mesh_vertices(mesh);
    const int *tri = rad_mesh_triangles(mesh), *parent = rad_mesh_input_faces(mesh);
    work = malloc(nn * 10 * sizeof *work);
    if (!work) {
        st = RAD_ERROR(RAD_ENOMEM, "solve: no memory for %d elements", n);
        agree(st);
        goto done;
    }
    double *rho = work, *E = work + 3 * nn, *B = work + 6 * nn, *area = work + 9 * nn;
    const int *tri_mat = rad_scene_triangle_materials(scene);
    const rad_scene_material *mats = rad_scene_materials(scene);
    for (size_t i = 0; i < nn; i++) {
        const rad_scene_material *mt = &mats[tri_mat[parent[i]]];
        double grey = (mt->rho[0] + mt->rho[1] + mt->rho[2]) / 3.0;
        for (int c = 0; c < 3; c++) {
            rho[i + c * nn] = sol.plan.colour.on ? mt->rho[c] : grey;
            E[i + c * nn] = mt->emission[c];
        }
        rad_vec3 t[3];
        for (int v = 0; v < 3; v++) {
            const double *q = xyz + 3 * (size_t)tri[3 * i + (size_t)v];
            t[v] = rad_vec3_make(q[0], q[1], q[2]);
        }
        area[i] = rad_geom_triangle_area(t[0], t[1], t[2]);
    }
    double t_setup = rad_sys_seconds();
    if (sol.plan.occlusion.on) {
        rad_vis_params vp;
        rad_vis_params_default(&vp);
        if ((st = rad_vis_create(rad_scene_vertices(scene), (size_t)rad_scene_vertex_count(scene),
                                 rad_scene_triangles(scene), (size_t)faces, &vp, &vis)) != RAD_OK) {
            agree(st);
            goto done;
        }
    }
    if ((st = agree(RAD_OK)) != RAD_OK) /* another rank could not get this far */
        goto done;
    p.assembly.face_of = parent;
    double t_vis = rad_sys_seconds();

    /* ---- the grid and this rank's blocks ---- */
    int nprow = 1;
    for (int d = 1; d * d <= ranks; d++)
        if (ranks % d == 0)
            nprow = d;
    int npcol = ranks / nprow, ctx, me, np, myrow, mycol, izero = 0, ione = 1, info = 0;
    Cblacs_pinfo(&me, &np);
    Cblacs_get(-1, 0, &ctx);
    Cblacs_gridinit(&ctx, "Row", nprow, npcol);
    Cblacs_gridinfo(ctx, &nprow, &npcol, &myrow, &mycol);
    int mloc = numroc_(&n, &nb, &myrow, &izero, &nprow);
    int nloc = numroc_(&n, &nb, &mycol, &izero, &npcol);
    int lld = mloc > 1 ? mloc : 1;
    size_t local = (size_t)lld * (size_t)(nloc > 0 ? nloc : 1);
    Gloc = calloc(local, sizeof *Gloc);
    Kloc = malloc(local * sizeof *Kloc);
    x = malloc(nn * 3 * sizeof *x);
    Bloc = calloc((size_t)lld * 3, sizeof *Bloc);
    if (!Gloc || !Kloc || !x || !Bloc)
        st = RAD_ERROR(RAD_ENOMEM, "solve: rank %d: no memory for its %d x %d blocks", rank, mloc,
                       nloc);
    if ((st = agree(st)) != RAD_OK)
        goto grid_done;
    rad_radiosity_stats as;
    memset(&as, 0, sizeof as);
    long long pairs = 0, not_facing = 0, tested = 0, evals = 0;
    unsigned long long rays = 0;
    rad_status first = RAD_OK;
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : pairs, not_facing, tested, evals, rays)
    for (int lj = 0; lj < nloc; lj++) {
        int j = global_index(lj, nb, mycol, npcol);
        for (int li = 0; li < mloc; li++) {
            int i = global_index(li, nb, myrow, nprow);
            if (i <= j) /* the lower triangle: each unordered pair once */
                continue;
            rad_radiosity_stats ps;
            memset(&ps, 0, sizeof ps);
            double g = 0.0;
            rad_status s = rad_radiosity_pair(xyz, tri, i, j, vis, &p.assembly, &g, &ps);
            if (s != RAD_OK) {
#pragma omp critical(radkit_mpi_error)
                first = first == RAD_OK ? s : first;
            }
            Gloc[(size_t)li + (size_t)lj * (size_t)lld] = g;
            pairs++;
            not_facing += ps.pairs_not_facing;
            tested += ps.pairs_occlusion_tested;
            evals += ps.kernel_evals;
            rays += ps.rays;
        }
    }
    if ((st = agree(first)) != RAD_OK)
        goto grid_done;
    /* a sealed scene's rows closed on the diagonal, as rad_radiosity_close_rows
       does serially: the row sums gathered (each stored G_ij, i > j, serves
       rows i and j), and each diagonal entry set on the rank that holds it */
    double rows_closed = 0.0;
    if (sol.plan.sealed) {
        double *rs = calloc(nn, sizeof *rs);
        if ((st = agree(rs ? RAD_OK : RAD_ERROR(RAD_ENOMEM, "solve: no memory"))) != RAD_OK) {
            free(rs);
            goto grid_done;
        }
        for (int lj = 0; lj < nloc; lj++) {
            int j = global_index(lj, nb, mycol, npcol);
            for (int li = 0; li < mloc; li++) {
                int i = global_index(li, nb, myrow, nprow);
                double g = Gloc[(size_t)li + (size_t)lj * (size_t)lld];
                if (i > j) {
                    rs[i] += g;
                    rs[j] += g;
                }
            }
        }
        MPI_Allreduce(MPI_IN_PLACE, rs, (int)nn, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
        for (int lj = 0; lj < nloc; lj++) {
            int j = global_index(lj, nb, mycol, npcol);
            for (int li = 0; li < mloc; li++)
                if (global_index(li, nb, myrow, nprow) == j)
                    Gloc[(size_t)li + (size_t)lj * (size_t)lld] = area[j] - rs[j];
        }
        for (size_t i = 0; i < nn; i++)
            rows_closed = fmax(rows_closed, fabs(area[i] - rs[i]) / area[i]);
        free(rs);
    }
    double t_assembled = rad_sys_seconds();

    /* ---- solve: the symmetric form, one pdposv per group of channels ----
     * For a reflecting face i, B = E + rho G B / A reads
     *   (A_i / rho_i) B_i - sum_{j reflecting} G_ij B_j
     *       = (A_i / rho_i) E_i + sum_{z not reflecting} G_iz E_z,
     * and B_z = E_z for the others: S = diag(A / rho) - G on the reflecting
     * faces (symmetric positive definite: rows of G sum to at most A, a closed
     * row's diagonal included), the
     * identity elsewhere.  Only S's lower triangle is read, as computed. */
    int descA[9], descB[9], three = 3;
    descinit_(descA, &n, &n, &nb, &nb, &izero, &izero, &ctx, &lld, &info);
    descinit_(descB, &n, &three, &nb, &nb, &izero, &izero, &ctx, &lld, &info);
    int done_c[3] = {0, 0, 0}, factorizations = 0;
    double *y = malloc(nn * 3 * sizeof *y);
    if ((st = agree(y ? RAD_OK : RAD_ERROR(RAD_ENOMEM, "solve: no memory"))) != RAD_OK) {
        free(y);
        goto grid_done;
    }
    memset(x, 0, nn * 3 * sizeof *x);
    for (int c = 0; c < 3 && st == RAD_OK; c++) {
        if (done_c[c])
            continue;
        int chans[3], nc = 0;
        for (int d = c; d < 3; d++) {
            int same = 1;
            for (size_t i = 0; i < nn && same; i++)
                same = rho[i + (size_t)d * nn] == rho[i + (size_t)c * nn];
            if (!done_c[d] && same) {
                chans[nc++] = d;
                done_c[d] = 1;
            }
        }
        const double *rc = rho + (size_t)c * nn;
        /* S's local entries, and this rank's share of the known faces' light */
        memset(y, 0, nn * 3 * sizeof *y);
        for (int lj = 0; lj < nloc; lj++) {
            int j = global_index(lj, nb, mycol, npcol);
            for (int li = 0; li < mloc; li++) {
                int i = global_index(li, nb, myrow, nprow);
                size_t k = (size_t)li + (size_t)lj * (size_t)lld;
                double g = Gloc[k];
                if (i == j)
                    Kloc[k] = rc[i] > 0.0 ? area[i] / rc[i] - g : 1.0;
                else if (i > j)
                    Kloc[k] = rc[i] > 0.0 && rc[j] > 0.0 ? -g : 0.0;
                else
                    Kloc[k] = 0.0;
                if (i > j && g != 0.0)
                    for (int r = 0; r < nc; r++) {
                        const double *e = E + (size_t)chans[r] * nn;
                        if (rc[i] > 0.0 && !(rc[j] > 0.0))
                            y[(size_t)i + (size_t)r * nn] += g * e[j];
                        if (rc[j] > 0.0 && !(rc[i] > 0.0))
                            y[(size_t)j + (size_t)r * nn] += g * e[i];
                    }
            }
        }
        MPI_Allreduce(MPI_IN_PLACE, y, (int)(3 * nn), MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
        /* the right-hand sides live in the first process column */
        memset(Bloc, 0, (size_t)lld * 3 * sizeof *Bloc);
        if (mycol == 0)
            for (int li = 0; li < mloc; li++) {
                int i = global_index(li, nb, myrow, nprow);
                for (int r = 0; r < nc; r++) {
                    double e = E[(size_t)i + (size_t)chans[r] * nn];
                    Bloc[(size_t)li + (size_t)r * (size_t)lld] =
                        rc[i] > 0.0 ? area[i] / rc[i] * e + y[(size_t)i + (size_t)r * nn] : e;
                }
            }
        pdposv_("L", &n, &nc, Kloc, &ione, &ione, descA, Bloc, &ione, &ione, descB, &info);
        factorizations++;
        if (info != 0) /* pdposv's info is the same on every rank */
            st = RAD_ERROR(RAD_ENUMERIC, "solve: pdposv failed (info %d): the system is not "
                                         "positive definite (a reflectance too close to 1?)",
                           info);
        if ((st = agree(st)) != RAD_OK) {
            free(y);
            goto grid_done;
        }
        if (mycol == 0)
            for (int li = 0; li < mloc; li++) {
                int i = global_index(li, nb, myrow, nprow);
                for (int r = 0; r < nc; r++)
                    x[(size_t)i + (size_t)chans[r] * nn] = Bloc[(size_t)li + (size_t)r * (size_t)lld];
            }
    }
    free(y);
    MPI_Allreduce(x, B, (int)(3 * nn), MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    /* the residual from the definition: r = E + rho G B / A - B, row sums
       gathered (each stored G_ij, i > j, serves rows i and j; a closed
       diagonal entry its own row) */
    memset(x, 0, nn * 3 * sizeof *x);
    for (int lj = 0; lj < nloc; lj++) {
        int j = global_index(lj, nb, mycol, npcol);
        for (int li = 0; li < mloc; li++) {
            int i = global_index(li, nb, myrow, nprow);
            double g = Gloc[(size_t)li + (size_t)lj * (size_t)lld];
            if (i < j || g == 0.0)
                continue;
            for (int c = 0; c < 3; c++) {
                x[(size_t)i + (size_t)c * nn] += g * B[(size_t)j + (size_t)c * nn];
                if (i > j)
                    x[(size_t)j + (size_t)c * nn] += g * B[(size_t)i + (size_t)c * nn];
            }
        }
    }
    MPI_Allreduce(MPI_IN_PLACE, x, (int)(3 * nn), MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    double residual = 0.0;
    for (int c = 0; c < 3; c++) {
        double rmax = 0.0, emax = 0.0;
        for (size_t i = 0; i < nn; i++) {
            size_t k = i + (size_t)c * nn;
            rmax = fmax(rmax, fabs(E[k] + rho[k] * x[k] / area[i] - B[k]));
            emax = fmax(emax, E[k]);
        }
        residual = fmax(residual, emax > 0.0 ? rmax / emax : rmax);
    }
    double t_solved = rad_sys_seconds();
    long long sums[4] = {pairs, not_facing, tested, evals}, tot[4];
    unsigned long long rays_tot = 0;
    MPI_Reduce(sums, tot, 4, MPI_LONG_LONG, MPI_SUM, 0, MPI_COMM_WORLD);
    MPI_Reduce(&rays, &rays_tot, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, 0, MPI_COMM_WORLD);
    double mem = rad_sys_peak_rss_bytes(), mem_max = 0.0;
    MPI_Reduce(&mem, &mem_max, 1, MPI_DOUBLE, MPI_MAX, 0, MPI_COMM_WORLD);
    if (st == RAD_OK && rank == 0) {
        sol.method = RAD_SOLVE_DENSE;
        sol.used = p;
        sol.faces = faces;
        sol.elements = nn;
        as.pairs = tot[0];
        as.pairs_not_facing = tot[1];
        as.pairs_occlusion_tested = tot[2];
        as.kernel_evals = tot[3];
        as.rays = rays_tot;
        sol.assembly = as;
        sol.assembly.rows_closed = rows_closed;
        sol.dense.method = RAD_DENSE_CHOLESKY;
        sol.dense.factorizations = factorizations;
        sol.dense.residual = residual;
        sol.dense.rcond = NAN; /* pdgecon is not run */
        sol.systems = factorizations;
        sol.phases[0] = (rad_solve_phase){"setup", t_setup - t_start};
        sol.phases[1] = (rad_solve_phase){"visibility", t_vis - t_setup};
        sol.phases[2] = (rad_solve_phase){"assemble", t_assembled - t_vis};
        sol.phases[3] = (rad_solve_phase){"solve", t_solved - t_assembled};
        sol.nphases = 4;
        sol.face_area = calloc((size_t)faces * 4, sizeof *sol.face_area);
        if (!sol.face_area) {
            st = RAD_ERROR(RAD_ENOMEM, "solve: no memory for %d faces", faces);
        } else {
            sol.face_B = sol.face_area + faces;
            st = rad_io_face_averages(nn, parent, area, B, (size_t)faces, sol.face_area,
                                      sol.face_B);
        }
        sol.total_seconds = rad_sys_seconds() - t_start;
        rad_io_output out = {0};
        if (st == RAD_OK && (st = rad_io_output_open(o->out ? o->out : "-", 0, &out)) == RAD_OK) {
            fprintf(out.f, "# ranks = %d\n# grid = %dx%d\n# block = %d\n"
                           "# memory_peak_bytes_per_rank = %.0f\n",
                    ranks, nprow, npcol, nb, mem_max);
            solve_print_table(out.f, o, scene, &sol);
            st = rad_io_output_commit(&out);
        }
        rad_io_output_discard(&out);
        if (st == RAD_OK && o->stats) {
            sol.solver_name = "scalapack-pdposv";
            sol.solver_residual = residual;
            sol.links = tot[0] - tot[1];
            sol.rays = rays_tot;
            sol.kernel_evals = tot[3];
            st = solve_write_stats_ranks(o->stats, &sol, 0.0, ranks, mem_max);
        }
        free(sol.face_area);
    }
grid_done:
    Cblacs_gridexit(ctx);
done:
    code = st == RAD_OK ? 0 : fail(rank, st);
    free(work);
    free(Gloc);
    free(Kloc);
    free(Bloc);
    free(x);
    rad_vis_destroy(vis);
    rad_mesh_destroy(mesh);
    rad_mesh_destroy(base);
    rad_scene_destroy(scene);
    MPI_Finalize();
    return code;
}
