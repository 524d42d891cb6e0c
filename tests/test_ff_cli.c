/* End to end: radkit ff, its output (DESIGN.md, "The command line") and its
 * answers to bad input. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"

static const char *T1 = "0 0 0  1 0 0  0 1 0";
static const char *T2 = "0 0 0, 0 0 1, 1 0 0"; /* commas are accepted too */

/* The data row after the header row; NULL if missing. */
static const char *data_row(const char *out)
{
    const char *h = strstr(out, "\nrule\tF12\tF21\tevals\tseconds\trel_error\tflags\tused\tadjacency\n");
    return h ? strchr(h + 1, '\n') + 1 : NULL;
}

TEST(cli_ff_every_rule_prints_one_row)
{
    const char *rules[] = {"vertex", "centroid", "gauss:4", "analytic:6", "ss:6", "exact", "auto"};
    for (size_t r = 0; r < sizeof rules / sizeof rules[0]; r++) {
        char *out, *err;
        int rc = harness_radkit_run(NULL, (const char *[]){"ff", "--tri", T1, "--tri", T2, "--rule", rules[r], NULL}, &out, &err);
        CHECK_MSG(rc == 0, "%s: exit %d, %s", rules[r], rc, err);
        CHECK(strcmp(err, "") == 0);
        const char *row = data_row(out);
        CHECK_MSG(row != NULL, "%s: no header row", rules[r]);
        if (row) {
            char name[32], flags[64], used[32], adj[16];
            double f12, f21, sec, rel;
            long evals;
            int n = sscanf(row, "%31s\t%lf\t%lf\t%ld\t%lf\t%lf\t%63s\t%31s\t%15s", name, &f12, &f21, &evals,
                           &sec, &rel, flags, used, adj);
            CHECK_MSG(n == 9, "%s: row '%s'", rules[r], row);
            CHECK(strcmp(name, rules[r]) == 0 && strcmp(adj, "edge") == 0);
            CHECK(f12 >= 0 && f12 < 1 && evals >= 1 && sec >= 0);
            CHECK(harness_count_lines(row) == 1);
            /* The two right-isosceles faces at 90 degrees: equal areas, F12 = F21. */
            CHECK_NEAR(f12, f21, 1e-15, 0.0);
            if (strcmp(rules[r], "exact") == 0 || strcmp(rules[r], "auto") == 0)
                CHECK(rel < 1e-6);
            if (strcmp(rules[r], "vertex") == 0)
                CHECK(strstr(flags, "guarded") != NULL);
        }
        free(out);
        free(err);
    }
}

TEST(cli_ff_auto_reports_its_choice_and_flags_out_of_range)
{
    char *out, *err;
    CHECK(harness_radkit_run(NULL, (const char *[]){"ff", "--tri", T1, "--tri", "0.2 0.1 7.3 0.3 1.1 7.2 1.2 0.2 7.4", "--rule",
                               "auto", "--tol", "1e-4", NULL},
              &out, &err) == 0);
    CHECK(strstr(out, "\tgauss:") != NULL); /* a far pair: a symmetric rule */
    CHECK(strstr(out, "# tol = 0.0001") != NULL);
    free(out);
    free(err);
    CHECK(harness_radkit_run(NULL, (const char *[]){"ff", "--tri", T1, "--tri", "0 0 1e-4 0 1 1e-4 1 0 1e-4", "--rule", "vertex", NULL},
              &out, &err) == 0);
    CHECK(strstr(out, "out_of_range") != NULL);
    free(out);
    free(err);
    /* Facing away: zero, flagged, no evaluations. */
    CHECK(harness_radkit_run(NULL, (const char *[]){"ff", "--tri", T1, "--tri", "0 0 1 1 0 1 0 1 1", NULL}, &out, &err) == 0);
    const char *row = data_row(out);
    CHECK(row && strncmp(row, "exact\t0\t0\t0\t", 12) == 0 && strstr(row, "not_facing"));
    free(out);
    free(err);
}

TEST(cli_ff_help_explains_every_option)
{
    char *out, *err;
    CHECK(harness_radkit_run(NULL, (const char *[]){"ff", "--help", NULL}, &out, &err) == 0);
    const char *words[] = {"--tri", "--rule", "--tol", "--repeat", "vertex", "centroid", "gauss:P",
                           "analytic:P", "ss:N", "exact", "auto", "rel_error", "flags"};
    for (size_t k = 0; k < sizeof words / sizeof words[0]; k++)
        CHECK_MSG(strstr(out, words[k]) != NULL, "help does not mention %s", words[k]);
    free(out);
    free(err);
    CHECK(harness_radkit_run(NULL, (const char *[]){"--help", NULL}, &out, &err) == 0);
    CHECK(strstr(out, "  ff ") != NULL);
    free(out);
    free(err);
}

TEST(cli_ff_bad_input_exits_2_with_one_line)
{
    struct {
        const char *args[12];
        const char *says;
    } cases[] = {
        {{"ff", "--tri", T1, "--tri", "0 0 0 1 1 1 2 2 2", NULL}, "degenerate"},
        {{"ff", "--tri", T1, "--tri", "0 0 0 1 0 0 1 0 0", NULL}, "degenerate"},
        {{"ff", "--tri", T1, "--tri", "0 0 1 nan 0 1 0 1 1", NULL}, "not finite"},
        {{"ff", "--tri", T1, "--tri", "0 0 1 inf 0 1 0 1 1", NULL}, "not finite"},
        {{"ff", "--tri", "0 0 0 1e200 0 0 0 1e200 0", "--tri", T2, NULL}, "scale the pair down"},
        {{"ff", "--tri", T1, "--tri", "0 0 1 1 0 1 0 1", NULL}, "expected 9 coordinates, got 8"},
        {{"ff", "--tri", T1, "--tri", "0 0 1 1 0 1 0 1 1 5", NULL}, "expected 9 coordinates, got 10"},
        {{"ff", "--tri", T1, "--tri", "0 0 1 1 0 x 0 1 1", NULL}, "not a number"},
        {{"ff", "--tri", T1, NULL}, "two --tri"},
        {{"ff", "--tri", T1, "--tri", T2, "--tri", T1, NULL}, "more than twice"},
        {{"ff", "--tri", T1, "--tri", T2, "--rule", "simpson", NULL}, "unknown rule"},
        {{"ff", "--tri", T1, "--tri", T2, "--rule", "gauss:41", NULL}, "unsupported order"},
        {{"ff", "--tri", T1, "--tri", T2, "--rule", "ss:0", NULL}, "unsupported order"},
        {{"ff", "--tri", T1, "--tri", T2, "--rule", "gauss", NULL}, "needs an order"},
        {{"ff", "--tri", T1, "--tri", T2, "--rule", "auto", "--tol", "0", NULL}, "--tol"},
        {{"ff", "--tri", T1, "--tri", T2, "--rule", "auto", "--tol", "-1e-6", NULL}, "--tol"},
        {{"ff", "--tri", T1, "--tri", T2, "--tol", "abc", NULL}, "--tol"},
        {{"ff", "--tri", T1, "--tri", T2, "--frobnicate", NULL}, "unknown option"},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        char *out, *err;
        int rc = harness_radkit_run(NULL, cases[k].args, &out, &err);
        CHECK_MSG(rc == 2, "case %zu: exit %d", k, rc);
        CHECK_MSG(strstr(err, cases[k].says) != NULL, "case %zu: stderr '%s' lacks '%s'", k, err, cases[k].says);
        CHECK_MSG(strncmp(err, "radkit: ", 8) == 0 && harness_count_lines(err) == 1, "case %zu: '%s'", k, err);
        CHECK(strcmp(out, "") == 0);
        free(out);
        free(err);
    }
}
