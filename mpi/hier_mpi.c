/* radkit-mpi solve --method hier|cluster: hierarchical radiosity with its
 * work shared among the MPI ranks.
 *
 * Every rank parses radkit solve's own options (cmd_solve.c's table), loads
 * the scene and runs radkit solve's pipeline (rad_solve_run) with the
 * library's exchange hook set (rad_hier_exchange over MPI, exchange.c):
 * each batch of link estimates is dealt among the ranks and all-gathered,
 * and (--gather shared, the default) each gather / push-pull step is cut by
 * input triangles and its values all-gathered; everything else (the oracle,
 * the tree, the cluster links' gather, the error bound's figures) is
 * replicated, so every rank holds the whole hierarchy, the serial one bit
 * for bit.  Rank 0 prints radkit solve's table and outputs
 * with `# ranks`, `# memory_peak_bytes_per_rank` (the largest rank's), the
 * exchanges' time (`# time_comm_s`, a part of link, refine and solve) and
 * the processor time of the solve outside the exchanges, the largest rank's
 * and the sum (`# cpu_work_max_rank_s`, `# cpu_work_sum_s`).  A
 * rank that fails by itself is agreed on before any rank waits (radkit_mpi.h). */
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "rad_io.h"
#include "rad_scene.h"
#include "rad_solve.h"
#include "rad_sys.h"
#include "radkit_mpi.h"
#include "solve.h"

static const char help[] =
    "usage: mpirun -np N radkit-mpi solve SCENE --method hier|cluster [--gather G]\n"
    "                    [radkit solve's options for hier and cluster]\n"
    "\n"
    "Hierarchical radiosity (radkit solve --method hier or cluster) with its work\n"
    "shared among the MPI ranks: the link estimates of every batch are dealt to\n"
    "the ranks and all-gathered; every rank keeps the whole hierarchy, so the\n"
    "answers are radkit solve's, bit for bit, and the memory per rank is the\n"
    "serial run's.  The table is radkit solve's, with '# ranks',\n"
    "'# memory_peak_bytes_per_rank' (the largest rank's) and time_comm_s (the\n"
    "exchanges, a part of link, refine and solve).\n"
    "\n"
    "  --gather G       shared (default): each gather / push-pull step is cut\n"
    "                   among the ranks by input triangles and its values\n"
    "                   all-gathered; replicated: every rank gathers every link\n";

int radkit_mpi_hier(int argc, char **argv, int rank, int ranks)
{
    solve_options o;
    const char *gather = NULL;
    cli_option table[SOLVE_OPTION_SLOTS + 1];
    int nopt = solve_option_table(&o, table);
    table[nopt++] = (cli_option){"--gather", &gather, NULL, NULL};
    table[nopt] = (cli_option){NULL, NULL, NULL, NULL};
    /* the same arguments everywhere: every rank fails alike until the
       pipeline, and only rank 0 speaks */
    rad_status st = cli_parse("solve", argc, argv, 2, table);
    if (st == RAD_OK && o.help) {
        if (rank == 0)
            fputs(help, stdout);
        return 0;
    }
    int split = 1;
    if (st == RAD_OK && gather && strcmp(gather, "shared") != 0 &&
        strcmp(gather, "replicated") != 0)
        st = RAD_ERROR(RAD_EINVAL, "solve: --gather must be shared or replicated, got '%s'",
                       gather);
    if (st == RAD_OK && gather)
        split = strcmp(gather, "shared") == 0;
    if (st == RAD_OK && !o.scene)
        st = RAD_ERROR(RAD_EINVAL, "solve: no scene given");
    if (st == RAD_OK && rank == 0)
        st = solve_check_outputs(&o); /* rank 0 writes them */
    rad_scene_params sp;
    rad_effects_params ep;
    rad_solve_params p;
    rad_scene_params_default(&sp);
    rad_scene_effects_params_default(&ep);
    if (st == RAD_OK)
        st = cli_scene_options_apply("solve", &o.scene_opts, &sp, &ep);
    if (st == RAD_OK)
        st = solve_parse_params(&o, &ep, &p);
    if (st == RAD_OK && p.method != RAD_SOLVE_HIER && p.method != RAD_SOLVE_CLUSTER)
        st = RAD_ERROR(RAD_EINVAL, "solve: this path runs --method hier or cluster");
    mpi_exchange x;
    rad_status xs = mpi_exchange_init(&x);
    if (st == RAD_OK)
        st = xs;
    rad_scene *scene = NULL;
    rad_solution *sol = NULL;
    double t0 = rad_sys_seconds(), cpu = 0.0;
    if (st == RAD_OK)
        st = rad_scene_load(o.scene, &sp, &scene);
    if (st == RAD_OK) {
        if (rank == 0 && !o.quiet) {
            for (int w = 0; w < rad_scene_warning_count(scene); w++)
                fprintf(stderr, "radkit: warning: %s\n", rad_scene_warning(scene, w));
            if (isatty(2)) {
                p.hier.progress = cli_hier_progress;
                p.hier.working = cli_hier_working;
                static char who[] = "radkit-mpi";
                p.hier.progress_ctx = who;
            }
        }
        mpi_exchange_hook(&x, split, &p.hier.exchange);
        cpu = mpi_cpu_seconds();
        st = rad_solve_run(scene, &p, &sol);
        cpu = mpi_cpu_seconds() - cpu;
        if (p.hier.progress)
            fputc('\n', stderr);
    }
    double t_run = rad_sys_seconds() - t0;
    /* who failed by itself: every rank learns the same lowest one */
    int failed = mpi_exchange_agree(&x, st);
    int code = 0;
    if (failed < ranks) {
        /* the lowest rank that failed by itself explains; the others
           (failed alike, or stopped by it) exit with its code, whichever
           process mpirun happens to see end first */
        if (rank == failed)
            code = cli_fail(st);
        if (code == 0)
            code = 1;
        if (MPI_Bcast(&code, 1, MPI_INT, failed, x.comm) != MPI_SUCCESS && code == 0)
            code = 1;
        goto done;
    }
    double mem = rad_sys_peak_rss_bytes(), mem_max = mem;
    if (MPI_Allreduce(&mem, &mem_max, 1, MPI_DOUBLE, MPI_MAX, x.comm) != MPI_SUCCESS)
        mem_max = mem;
    /* the processor time of the solve outside the exchanges: each rank's
       share of the work, which other work on the machine does not inflate
       the way it inflates wall time and the exchanges' waits */
    double slowest = t_run, work = cpu - x.cpu_s, work_max = work, work_sum = work;
    MPI_Allreduce(&t_run, &slowest, 1, MPI_DOUBLE, MPI_MAX, x.comm);
    MPI_Allreduce(&work, &work_max, 1, MPI_DOUBLE, MPI_MAX, x.comm);
    MPI_Allreduce(&work, &work_sum, 1, MPI_DOUBLE, MPI_SUM, x.comm);
    if (rank == 0) {
        rad_io_output out = {0};
        if ((st = rad_io_output_open(o.out ? o.out : "-", 0, &out)) == RAD_OK) {
            fprintf(out.f, "# ranks = %d\n# gather = %s\n# memory_peak_bytes_per_rank = %.0f\n"
                           "# time_slowest_rank_s = %.4f\n# cpu_work_max_rank_s = %.4f\n"
                           "# cpu_work_sum_s = %.4f\n",
                    ranks, split ? "shared" : "replicated", mem_max, slowest, work_max,
                    work_sum);
            solve_print_table(out.f, &o, scene, sol);
            st = rad_io_output_commit(&out);
        }
        rad_io_output_discard(&out);
        double render_s = 0.0;
        if (st == RAD_OK && (o.ply || o.png))
            st = solve_write_display(&o, scene, sol, &render_s);
        if (st == RAD_OK && o.stats)
            st = solve_write_stats_ranks(o.stats, sol, render_s, ranks, mem_max);
        code = st == RAD_OK ? 0 : cli_fail(st);
    }
done:
    rad_solution_destroy(sol);
    rad_scene_destroy(scene);
    mpi_exchange_destroy(&x);
    return code;
}
