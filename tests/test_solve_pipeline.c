/* rad_solve_run, the library's pipeline, called directly: every method
 * against the furnace's exact answer, the program's table against the
 * library's numbers, and each decision of the effects plan changing what
 * runs (and each override honoured or refused by name). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "rad_solve.h"

/* The scene at `rel` (repository-relative), every face reflecting rho (grey)
 * and emitting E, or as its materials say when rho < 0. */
static rad_scene *load(const char *rel, double rho, double E)
{
    rad_scene_params sp;
    rad_scene_params_default(&sp);
    if (rho >= 0.0) {
        sp.has_rho = sp.has_emission = 1;
        for (int c = 0; c < 3; c++) {
            sp.rho[c] = rho;
            sp.emission[c] = E;
        }
    }
    return harness_scene_load(rel, &sp);
}

static rad_solution *run(const rad_scene *scene, const rad_solve_params *p)
{
    rad_solution *s = NULL;
    rad_status st = rad_solve_run(scene, p, &s);
    CHECK_MSG(st == RAD_OK, "rad_solve_run: %s", rad_error_message());
    return s;
}

/* The largest relative deviation of any face and channel from b. */
static double furnace_error(const rad_solution *s, double b)
{
    double worst = 0.0;
    for (int i = 0; i < 3 * s->faces; i++)
        worst = fmax(worst, fabs(s->face_B[i] - b) / b);
    return worst;
}

TEST(solve_pipeline_furnace_every_method)
{
    /* closed convex cube, every face E = 1, rho = 0.9: B = E / (1 - rho) = 10 */
    rad_scene *scene = load("scenes/furnace_cube/cube.obj", 0.9, 1.0);
    rad_solve_params p;
    rad_solve_params_default(&p);
    rad_solution *s = run(scene, &p);
    CHECK_MSG(furnace_error(s, 10.0) < 5e-3, "dense: %g", furnace_error(s, 10.0));
    CHECK(s->faces == 12 && s->elements == 12 && s->rays == 0 && s->face_se == NULL);
    CHECK(s->nphases == 4 && strcmp(s->phases[2].name, "assemble") == 0);
    rad_solution_destroy(s);
    p.method = RAD_SOLVE_HIER;
    p.hier.eps = 0.01;
    s = run(scene, &p);
    CHECK_MSG(furnace_error(s, 10.0) < 1e-2, "hier: %g", furnace_error(s, 10.0));
    CHECK(s->hier.links > 0 && s->used.hier.min_area > 0.0); /* min_area followed eps */
    rad_solution_destroy(s);
    p.method = RAD_SOLVE_MC;
    p.mc.samples = 1024;
    s = run(scene, &p);
    CHECK(s->face_se != NULL);
    for (int i = 0; i < 3 * s->faces; i++)
        CHECK_MSG(fabs(s->face_B[i] - 10.0) <= 5.0 * s->face_se[i] + 1e-12,
                  "mc face %d: %g +- %g", i % s->faces, s->face_B[i], s->face_se[i]);
    rad_solution_destroy(s);
    rad_scene_destroy(scene);
}

/* The program is a thin layer: its table holds the library's numbers. */
TEST(solve_pipeline_program_prints_the_library_answer)
{
    rad_scene *scene = load("scenes/cornell/cornell.obj", -1.0, 0.0);
    rad_solve_params p;
    rad_solve_params_default(&p);
    p.method = RAD_SOLVE_HIER;
    rad_solution *s = run(scene, &p);
    char *out, *err;
    const char *args[] = {harness_path("scenes/cornell/cornell.obj"), "--method", "hier",
                          "--quiet", NULL};
    CHECK(harness_radkit_run("solve", args, &out, &err) == 0);
    double B[3 * 64];
    int n = harness_face_table(out, B, 64);
    CHECK(n == s->faces);
    for (int i = 0; i < n; i++)
        for (int c = 0; c < 3; c++) {
            double lib = s->face_B[i + c * s->faces];
            CHECK_MSG(fabs(B[3 * i + c] - lib) <= 1e-5 * fabs(lib) + 1e-9,
                      "face %d channel %d: table %g, library %g", i, c, B[3 * i + c], lib);
        }
    free(out);
    free(err);
    rad_solution_destroy(s);
    rad_scene_destroy(scene);
}

TEST(solve_plan_colour_decides_the_systems)
{
    /* grey furnace: one factorization; colour forced on: three, same answer */
    rad_scene *cube = load("scenes/furnace_cube/cube.obj", 0.5, 1.0);
    rad_solve_params p;
    rad_solve_params_default(&p);
    rad_solution *grey = run(cube, &p);
    CHECK(grey->systems == 1 && grey->plan.colour.on == 0);
    p.effects.colour = RAD_EFFECT_ON;
    rad_solution *three = run(cube, &p);
    CHECK(three->systems == 3 && three->plan.colour.forced);
    for (int i = 0; i < 3 * grey->faces; i++)
        CHECK(fabs(grey->face_B[i] - three->face_B[i]) <= 1e-12 * grey->face_B[i]);
    rad_solution_destroy(grey);
    rad_solution_destroy(three);
    rad_scene_destroy(cube);
    /* Cornell (coloured walls) with colour off: one system with the
     * channel-mean reflectance, so a channel ratio of the light's emission
     * holds on every face: B_c = (I - rho F)^-1 E_c with one matrix */
    rad_scene *cornell = load("scenes/cornell/cornell.obj", -1.0, 0.0);
    rad_solve_params_default(&p);
    p.effects.colour = RAD_EFFECT_OFF;
    rad_solution *s = run(cornell, &p);
    CHECK(s->systems == 1);
    int n = s->faces, lit = -1;
    for (int i = 0; i < n && lit < 0; i++)
        if (s->face_B[i] > 0.0 && s->face_B[i + n] > 0.0)
            lit = i;
    CHECK(lit >= 0);
    double rg = s->face_B[lit] / s->face_B[lit + n], rb = s->face_B[lit] / s->face_B[lit + 2 * n];
    for (int i = 0; i < n; i++) {
        CHECK_NEAR(s->face_B[i], rg * s->face_B[i + n], 1e-9, 1e-12);
        CHECK_NEAR(s->face_B[i], rb * s->face_B[i + 2 * n], 1e-9, 1e-12);
    }
    /* and with colour on (automatic) the red and green walls break the ratio */
    p.effects.colour = RAD_EFFECT_AUTO;
    rad_solution *c3 = run(cornell, &p);
    CHECK(c3->systems == 3);
    double spread = 0.0;
    for (int i = 0; i < n; i++)
        spread = fmax(spread, fabs(c3->face_B[i] - rg * c3->face_B[i + n]) / c3->face_B[i]);
    CHECK_MSG(spread > 0.1, "coloured walls change the channel ratio: %g", spread);
    rad_solution_destroy(s);
    rad_solution_destroy(c3);
    rad_scene_destroy(cornell);
}

TEST(solve_plan_facing_away_and_singular_overrides_act)
{
    /* facing-away off: those pairs are integrated (to zero): same answer, more
     * work (the Cornell box: 312 pairs face away) */
    rad_scene *cornell = load("scenes/cornell/cornell.obj", -1.0, 0.0);
    rad_solve_params p;
    rad_solve_params_default(&p);
    rad_solution *facing = run(cornell, &p);
    CHECK(facing->assembly.pairs_not_facing == 312);
    p.effects.facing_away = RAD_EFFECT_OFF;
    rad_solution *all = run(cornell, &p);
    CHECK(all->assembly.pairs_not_facing == 0);
    CHECK(all->kernel_evals > facing->kernel_evals);
    for (int i = 0; i < 3 * facing->faces; i++)
        CHECK_NEAR(all->face_B[i], facing->face_B[i], 1e-12, 0.0);
    rad_solution_destroy(facing);
    rad_scene_destroy(cornell);
    rad_scene *cube = load("scenes/furnace_cube/cube.obj", 0.9, 1.0);
    rad_solve_params_default(&p);
    rad_solution *base = run(cube, &p);
    /* singular off: the touching pairs by the regular Gauss ladder, which the
     * kernel's singularity keeps from converging: the rows miss their areas
     * by more than with the singular rules (rows_closed); closed on the
     * diagonal, both hold the furnace */
    p.effects.singular = RAD_EFFECT_OFF;
    rad_solution *reg = run(cube, &p);
    double r_on = base->assembly.rows_closed, r_off = reg->assembly.rows_closed;
    CHECK_MSG(r_off > 2.0 * r_on && r_on < 5e-3, "singular on %g, off %g", r_on, r_off);
    double e_on = furnace_error(base, 10.0), e_off = furnace_error(reg, 10.0);
    CHECK_MSG(e_on < 1e-12 && e_off < 1e-12, "furnace: singular on %g, off %g", e_on, e_off);
    CHECK(reg->used.assembly.ff.singular_rules == 0);
    /* hier: touching elements by point values when off */
    p.method = RAD_SOLVE_HIER;
    rad_solution *h = run(cube, &p);
    CHECK(h->used.hier.singular == 0);
    rad_solution_destroy(h);
    rad_solution_destroy(base);
    rad_solution_destroy(all);
    rad_solution_destroy(reg);
    rad_scene_destroy(cube);
}

TEST(solve_plan_occlusion_and_reflectance_overrides_act)
{
    rad_scene *cornell = load("scenes/cornell/cornell.obj", -1.0, 0.0);
    rad_solve_params p;
    rad_solve_params_default(&p);
    rad_solution *vis = run(cornell, &p);
    CHECK(vis->plan.occlusion.on && vis->assembly.pairs_occlusion_tested > 0);
    p.effects.occlusion = RAD_EFFECT_OFF;
    rad_solution *open = run(cornell, &p);
    CHECK(open->rays == 0 && open->assembly.pairs_occlusion_tested == 0);
    double most = 0.0; /* without the blocks' shadows the floor is brighter */
    for (int i = 0; i < 3 * vis->faces; i++)
        most = fmax(most, fabs(open->face_B[i] - vis->face_B[i]) / (vis->face_B[i] + 1e-12));
    CHECK_MSG(most > 0.05, "occlusion off changes the answer: %g", most);
    rad_solution_destroy(vis);
    rad_solution_destroy(open);
    rad_scene_destroy(cornell);
    /* reflectance near 1 tightens the defaults' tolerances; off keeps them */
    rad_scene *cube = load("scenes/furnace_cube/cube.obj", 0.99, 1.0);
    rad_solve_params_default(&p);
    double tol = p.assembly.ff.tol;
    rad_solution *tight = run(cube, &p);
    CHECK_NEAR(tight->used.assembly.ff.tol, tol * 0.01 / 0.5, 1e-12, 0.0);
    p.effects.reflectance = RAD_EFFECT_OFF;
    rad_solution *loose = run(cube, &p);
    CHECK(loose->used.assembly.ff.tol == tol);
    /* a tolerance the caller chose is kept */
    p.effects.reflectance = RAD_EFFECT_AUTO;
    p.assembly.ff.tol = 1e-4;
    p.keep_tol = 1;
    rad_solution *kept = run(cube, &p);
    CHECK(kept->used.assembly.ff.tol == 1e-4);
    rad_solution_destroy(tight);
    rad_solution_destroy(loose);
    rad_solution_destroy(kept);
    rad_scene_destroy(cube);
}

TEST(solve_plan_overrides_a_method_cannot_honour_are_refused)
{
    rad_scene *cube = load("scenes/furnace_cube/cube.obj", 0.5, 1.0);
    rad_solve_params p;
    rad_solve_params_default(&p);
    rad_solution *s = (rad_solution *)1;
    p.method = RAD_SOLVE_MC;
    p.effects.singular = RAD_EFFECT_OFF;
    CHECK(rad_solve_run(cube, &p, &s) == RAD_EINVAL && s == NULL);
    CHECK(strstr(rad_error_message(), "--method mc") != NULL);
    p.effects.singular = RAD_EFFECT_AUTO;
    p.effects.facing_away = RAD_EFFECT_OFF;
    p.method = RAD_SOLVE_HIER;
    CHECK(rad_solve_run(cube, &p, &s) == RAD_EINVAL && s == NULL);
    CHECK(strstr(rad_error_message(), "facing-away") != NULL);
    /* and the program says the same, exit 2 */
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){harness_path("scenes/furnace_cube/cube.obj"),
                               "--method", "mc", "--singular", "off", NULL}, "--method mc");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){harness_path("scenes/furnace_cube/cube.obj"),
                               "--method", "hier", "--refine", "1", NULL}, "--refine");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){harness_path("scenes/furnace_cube/cube.obj"),
                               "--eps", "0.1", NULL}, "--eps");
    rad_scene_destroy(cube);
    CHECK(rad_solve_run(NULL, &p, &s) == RAD_EINVAL);
}
