/* End to end: the radkit program's galerkin1d subcommand, its output format
 * (DESIGN.md, "The command line") and its answers to bad input. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"

TEST(cli_help_explains_every_option)
{
    char *out, *err;
    CHECK(harness_radkit_run(NULL, (const char *[]){"--help", NULL}, &out, &err) == 0);
    CHECK(strstr(out, "galerkin1d") != NULL);
    free(out);
    free(err);
    CHECK(harness_radkit_run(NULL, (const char *[]){"galerkin1d", "--help", NULL}, &out, &err) == 0);
    const char *opts[] = {"--n", "--problem", "--basis", "--assembly", "gauss:K", "midpoint",
                          "exact", "seed", "exp", "p0", "p1", "--no-check"};
    for (size_t k = 0; k < sizeof opts / sizeof opts[0]; k++)
        CHECK_MSG(strstr(out, opts[k]) != NULL, "help does not mention %s", opts[k]);
    free(out);
    free(err);
    CHECK(harness_radkit_run(NULL, (const char *[]){"--version", NULL}, &out, &err) == 0);
    CHECK(strncmp(out, "radkit ", 7) == 0);
    free(out);
    free(err);
}

TEST(cli_galerkin1d_p0_output_format)
{
    char *out, *err, buf[128];
    CHECK(harness_radkit_run(NULL, (const char *[]){"galerkin1d", "--n", "5", NULL}, &out, &err) == 0);
    CHECK(strcmp(err, "") == 0);
    const char *table = strstr(out, "\ni\tx\ty\ty_exact\n");
    CHECK(table != NULL);
    if (!table) {
        free(out);
        free(err);
        return;
    }
    const char *keys[] = {"problem", "basis", "assembly", "n", "err_l2", "err_linf", "err_nodal",
                          "err_coef", "galerkin_residual", "rcond", "cond1_estimate", "solve_s",
                          "assemble_s"};
    for (size_t k = 0; k < sizeof keys / sizeof keys[0]; k++)
        CHECK_MSG(harness_header(out, keys[k], buf, sizeof buf) != NULL, "no '# %s' line", keys[k]);
    /* Seed, P0, exact: the coefficients are the cell means of y = x, i.e. x. */
    const char *row = table + 1;
    int rows = 0;
    for (const char *line = strchr(row, '\n') + 1; *line; line = strchr(line, '\n') + 1) {
        int i;
        double x, y, ye;
        CHECK(sscanf(line, "%d\t%lf\t%lf\t%lf", &i, &x, &y, &ye) == 4);
        CHECK(i == rows);
        CHECK_NEAR(x, (rows + 0.5) / 5.0, 1e-15, 0.0);
        CHECK_NEAR(y, x, 0.0, 1e-14);
        rows++;
    }
    CHECK(rows == 5);
    const char *res = harness_header(out, "galerkin_residual", buf, sizeof buf);
    CHECK(res && atof(res) < 1e-13);
    free(out);
    free(err);
}

TEST(cli_galerkin1d_p1_and_quadrature)
{
    char *out, *err, buf[128];
    CHECK(harness_radkit_run(NULL, (const char *[]){"galerkin1d", "--n=8", "--problem", "exp", "--basis", "p1",
                               "--assembly", "gauss:2", NULL}, &out, &err) == 0);
    const char *table = strstr(out, "\ni\t");
    CHECK(table && harness_count_lines(table + 1) == 1 + 9);
    const char *assembly = harness_header(out, "assembly", buf, sizeof buf);
    CHECK(assembly && strcmp(assembly, "gauss:2") == 0);
    const char *coef_text = harness_header(out, "err_coef", buf, sizeof buf);
    double coef = coef_text ? atof(coef_text) : NAN;
    CHECK_MSG(coef > 1e-6 && coef < 1e-2, "err_coef = %g", coef); /* quadrature error is seen */
    free(out);
    free(err);
}

TEST(cli_galerkin1d_rejects_bad_input)
{
    HARNESS_EXPECT_USAGE_ERROR(NULL, (const char *[]){"galerkin1d", "--n", "0", NULL}, "--n");
    HARNESS_EXPECT_USAGE_ERROR(NULL, (const char *[]){"galerkin1d", "--n", "-3", NULL}, "--n");
    HARNESS_EXPECT_USAGE_ERROR(NULL, (const char *[]){"galerkin1d", "--n", "abc", NULL}, "abc");
    HARNESS_EXPECT_USAGE_ERROR(NULL, (const char *[]){"galerkin1d", "--n", "12abc", NULL}, "12abc");
    HARNESS_EXPECT_USAGE_ERROR(NULL, (const char *[]){"galerkin1d", "--n", "", NULL}, "--n");
    HARNESS_EXPECT_USAGE_ERROR(NULL, (const char *[]){"galerkin1d", "--n", "99999999999999999999999", NULL}, "--n");
    HARNESS_EXPECT_USAGE_ERROR(NULL, (const char *[]){"galerkin1d", NULL}, "--n");
    HARNESS_EXPECT_USAGE_ERROR(NULL, (const char *[]){"galerkin1d", "--n", NULL}, "--n");
    HARNESS_EXPECT_USAGE_ERROR(NULL, (const char *[]){"galerkin1d", "--n", "4", "--problem", "heat", NULL}, "heat");
    HARNESS_EXPECT_USAGE_ERROR(NULL, (const char *[]){"galerkin1d", "--n", "4", "--basis", "p2", NULL}, "p2");
    HARNESS_EXPECT_USAGE_ERROR(NULL, (const char *[]){"galerkin1d", "--n", "4", "--assembly", "gauss:0", NULL}, "gauss:0");
    HARNESS_EXPECT_USAGE_ERROR(NULL, (const char *[]){"galerkin1d", "--n", "4", "--assembly", "simpson", NULL}, "simpson");
    HARNESS_EXPECT_USAGE_ERROR(NULL, (const char *[]){"galerkin1d", "--n", "4", "--frobnicate", NULL}, "--frobnicate");
    HARNESS_EXPECT_USAGE_ERROR(NULL, (const char *[]){"galerkin1d", "--n", "100000", NULL}, "dense");
    HARNESS_EXPECT_USAGE_ERROR(NULL, (const char *[]){"galerkin1d", "--n", "2000000000", NULL}, "--n");
    HARNESS_EXPECT_USAGE_ERROR(NULL, (const char *[]){"frobnicate", NULL}, "frobnicate");
}

TEST(cli_galerkin1d_refuses_what_memory_cannot_hold)
{
    /* 3000 unknowns need 69 MiB: refuse on a machine said to have 64 MiB. */
    setenv("RADKIT_MEMORY_LIMIT", "67108864", 1);
    HARNESS_EXPECT_USAGE_ERROR(NULL, (const char *[]){"galerkin1d", "--n", "3000", NULL}, "GiB");
    unsetenv("RADKIT_MEMORY_LIMIT");
}
