/* Every file radkit writes (solve --out, --ply, --png, --stats) and its
 * standard output: a path that cannot be written is a usage error (exit 2,
 * one message naming the path and the problem), a failed write is exit 1
 * with nothing left behind but what was there before, nothing radkit did not
 * create is ever removed, and one path given to two outputs is refused.
 * Every test works in its own directory under /tmp and removes it. */
#define _DEFAULT_SOURCE /* mknod, makedev */
#include "harness.h"

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#define SCENE "scenes/tetrahedron/tetrahedron.obj"

static char *make_dir(void)
{
    char *d = strdup("/tmp/radkit-outputs-XXXXXX");
    if (!mkdtemp(d)) {
        free(d);
        return NULL;
    }
    return d;
}

/* Remove dir and what the tests put in it (files, links, device nodes, one
 * level of subdirectories); never follows a link. */
static void remove_dir(const char *dir)
{
    DIR *d = opendir(dir);
    if (d) {
        struct dirent *e;
        char path[1024];
        while ((e = readdir(d)) != NULL) {
            if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0)
                continue;
            snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
            struct stat st;
            if (lstat(path, &st) == 0 && S_ISDIR(st.st_mode))
                remove_dir(path);
            else
                unlink(path);
        }
        closedir(d);
    }
    rmdir(dir);
}

static int count_entries(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d)
        return -1;
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL)
        n += strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0;
    closedir(d);
    return n;
}

static int dev_full_ok(void)
{
    struct stat st;
    return stat("/dev/full", &st) == 0 && S_ISCHR(st.st_mode);
}

static const char *const methods[3] = {"dense", "hier", "mc"};

TEST(outputs_unwritable_path_is_a_usage_error)
{
    char *dir = make_dir();
    CHECK(dir != NULL);
    if (!dir)
        return;
    char missing[512];
    snprintf(missing, sizeof missing, "%s/no-such-dir/x.out", dir);
    const char *options[4] = {"--out", "--ply", "--png", "--stats"};
    const char *paths[3] = {missing, "", dir};
    const char *problems[3] = {"does not exist", "empty", "directory"};
    for (int m = 0; m < 3; m++)
        for (int o = 0; o < 4; o++)
            for (int p = 0; p < 3; p++) {
                const char *args[] = {harness_path(SCENE), "--method", methods[m], "--quiet",
                                      options[o], paths[p], NULL};
                char *out, *err;
                int code = harness_radkit_run("solve", args, &out, &err);
                CHECK_MSG(code == 2, "%s %s '%s': exit %d, want 2 (%s)", methods[m], options[o],
                          paths[p], code, err);
                CHECK_MSG(harness_count_lines(err) == 1 && strncmp(err, "radkit: ", 8) == 0,
                          "%s %s '%s': stderr %s", methods[m], options[o], paths[p], err);
                CHECK_MSG(strstr(err, problems[p]) && strstr(err, options[o]),
                          "%s %s '%s': message '%s' does not say '%s'", methods[m], options[o],
                          paths[p], err, problems[p]);
                if (p != 1)
                    CHECK_MSG(strstr(err, paths[p]) != NULL, "message '%s' does not name %s", err,
                              paths[p]);
                free(out);
                free(err);
            }
    struct stat st;
    CHECK(stat(dir, &st) == 0 && S_ISDIR(st.st_mode));
    CHECK(count_entries(dir) == 0);
    remove_dir(dir);
    free(dir);
}

TEST(outputs_failed_write_never_removes_the_target)
{
    if (!dev_full_ok()) {
        printf("    (skipped: no /dev/full)\n");
        return;
    }
    char *dir = make_dir();
    CHECK(dir != NULL);
    if (!dir)
        return;
    /* A link to /dev/full, and (where allowed) a device node of our own with
     * /dev/full's numbers: writes fail with ENOSPC, and both must survive. */
    char link[512], node[512];
    snprintf(link, sizeof link, "%s/full-link", dir);
    snprintf(node, sizeof node, "%s/full-node", dir);
    CHECK(symlink("/dev/full", link) == 0);
    int have_node = mknod(node, S_IFCHR | 0666, makedev(1, 7)) == 0;
    const char *options[4] = {"--out", "--ply", "--png", "--stats"};
    for (int m = 0; m < 3; m++)
        for (int o = 0; o < 4; o++)
            for (int t = 0; t < 1 + have_node; t++) {
                const char *target = t ? node : link;
                const char *args[] = {harness_path(SCENE), "--method", methods[m], "--quiet",
                                      options[o], target, NULL};
                char *out, *err;
                int code = harness_radkit_run("solve", args, &out, &err);
                CHECK_MSG(code == 1, "%s %s %s: exit %d, want 1 (%s)", methods[m], options[o],
                          target, code, err);
                CHECK_MSG(strstr(err, "No space left on device") != NULL, "%s %s: stderr %s",
                          methods[m], options[o], err);
                struct stat st;
                CHECK_MSG(lstat(target, &st) == 0, "%s %s: %s was removed", methods[m], options[o],
                          target);
                free(out);
                free(err);
            }
    CHECK(dev_full_ok());
    CHECK(count_entries(dir) == 1 + have_node); /* no temporary file left */
    remove_dir(dir);
    free(dir);
}

/* Run radkit with its standard output on /dev/full (through /bin/sh). */
static int run_to_dev_full(const char *const args[], char **err)
{
    const char *argv[40] = {"/bin/sh", "-c", "exec \"$@\" > /dev/full", "sh", harness_radkit()};
    int k = 5;
    for (int a = 0; args[a] && k < 39; a++)
        argv[k++] = args[a];
    argv[k] = NULL;
    char *out;
    int code = harness_run(argv, &out, err);
    free(out);
    return code;
}

TEST(outputs_standard_output_write_error_exits_1)
{
    if (!dev_full_ok()) {
        printf("    (skipped: no /dev/full)\n");
        return;
    }
    char *dir = make_dir();
    CHECK(dir != NULL);
    if (!dir)
        return;
    char table[512];
    snprintf(table, sizeof table, "%s/t.tsv", dir);
    const char *make[] = {harness_path(SCENE), "--quiet", "--out", table, NULL};
    char *o0, *e0;
    CHECK(harness_radkit_run("solve", make, &o0, &e0) == 0);
    free(o0);
    free(e0);
    const char *scene = harness_path(SCENE);
    const char *cases[][12] = {
        {"--version", NULL},
        {"--help", NULL},
        {"galerkin1d", "--n", "4", NULL},
        {"galerkin1d", "--help", NULL},
        {"info", scene, NULL},
        {"ff", "--tri", "0 0 0 1 0 0 0 1 0", "--tri", "0 0 1 0 1 1 1 0 1", NULL},
        {"solve", scene, "--quiet", NULL},
        {"solve", scene, "--quiet", "--method", "hier", NULL},
        {"solve", scene, "--quiet", "--method", "mc", "--samples", "64", NULL},
        {"solve", scene, "--quiet", "--out", "-", NULL},
        {"solve", "--help", NULL},
        {"compare", scene, table, table, NULL},
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        char *err;
        int code = run_to_dev_full(cases[c], &err);
        CHECK_MSG(code == 1, "%s %s > /dev/full: exit %d, want 1 (%s)", cases[c][0],
                  cases[c][1] ? cases[c][1] : "", code, err);
        CHECK_MSG(strstr(err, "radkit: error writing standard output: No space left on device"),
                  "%s: stderr %s", cases[c][0], err);
        free(err);
    }
    CHECK(dev_full_ok());
    remove_dir(dir);
    free(dir);
}

/* radkit with a file-size limit (writes beyond it fail with EFBIG),
 * standard output on /dev/null; returns the exit status, stderr in *err. */
static int run_with_size_limit(const char *const args[], long limit, char **err)
{
    char err_name[] = "/tmp/radkit-outputs-err-XXXXXX";
    int fe = mkstemp(err_name);
    unlink(err_name);
    const char *argv[40] = {harness_radkit()};
    int k = 1;
    for (int a = 0; args[a] && k < 39; a++)
        argv[k++] = args[a];
    argv[k] = NULL;
    fflush(stdout);
    pid_t pid = fork();
    if (pid == 0) {
        int null_fd = open("/dev/null", O_RDWR);
        dup2(null_fd, 0);
        dup2(null_fd, 1);
        dup2(fe, 2);
        signal(SIGXFSZ, SIG_IGN);
        struct rlimit rl = {(rlim_t)limit, (rlim_t)limit};
        setrlimit(RLIMIT_FSIZE, &rl);
        execv(argv[0], (char *const *)argv);
        _exit(127);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    off_t len = lseek(fe, 0, SEEK_END);
    *err = calloc((size_t)len + 1, 1);
    if (len > 0 && pread(fe, *err, (size_t)len, 0) < 0)
        (*err)[0] = '\0';
    close(fe);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(outputs_failed_write_leaves_no_partial_file)
{
    char *dir = make_dir();
    CHECK(dir != NULL);
    if (!dir)
        return;
    char target[512];
    snprintf(target, sizeof target, "%s/mesh.ply", dir);
    /* --refine 3: a PLY of a few tens of kB against a 4 kB limit; the table
     * goes to /dev/null. */
    const char *ply[] = {"solve", harness_path(SCENE), "--quiet", "--refine", "3", "--ply", target,
                         NULL};
    const char *out[] = {"solve", harness_path(SCENE), "--quiet", "--refine", "3", "--out", target,
                         NULL};
    const char *const *cases[2] = {ply, out};
    const long limit[2] = {4096, 512}; /* the table is about 2 kB */
    for (int c = 0; c < 2; c++) {
        char *err;
        int code = run_with_size_limit(cases[c], limit[c], &err);
        CHECK_MSG(code == 1, "case %d: exit %d, want 1 (%s)", c, code, err);
        CHECK_MSG(strstr(err, target) != NULL, "case %d: message '%s' does not name the file", c,
                  err);
        CHECK_MSG(count_entries(dir) == 0, "case %d: %d files left in %s", c, count_entries(dir),
                  dir);
        free(err);
        /* an existing file keeps its old contents */
        FILE *f = fopen(target, "w");
        CHECK(f != NULL);
        if (f) {
            fputs("old contents\n", f);
            fclose(f);
        }
        code = run_with_size_limit(cases[c], limit[c], &err);
        CHECK(code == 1);
        char *text = harness_read_file(target);
        CHECK_MSG(text && strcmp(text, "old contents\n") == 0, "case %d: the old file was changed",
                  c);
        CHECK(count_entries(dir) == 1);
        free(text);
        free(err);
        unlink(target);
    }
    remove_dir(dir);
    free(dir);
}

TEST(outputs_one_path_for_two_outputs_is_refused)
{
    char *dir = make_dir();
    CHECK(dir != NULL);
    if (!dir)
        return;
    char x[512], y[512], hard[512], soft[512];
    snprintf(x, sizeof x, "%s/x", dir);
    snprintf(y, sizeof y, "%s/sub/../x", dir);
    snprintf(hard, sizeof hard, "%s/hard", dir);
    snprintf(soft, sizeof soft, "%s/soft", dir);
    char sub[512];
    snprintf(sub, sizeof sub, "%s/sub", dir);
    CHECK(mkdir(sub, 0755) == 0);
    const char *scene = harness_path(SCENE);
    /* the same string */
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){scene, "--out", x, "--png", x, NULL},
                               "--out");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){scene, "--out", x, "--png", x, NULL},
                               "--png");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){scene, "--method", "hier", "--stats", x,
                                                        "--ply", x, NULL},
                               "--stats");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){scene, "--method", "mc", "--out", "-",
                                                        "--stats", "-", NULL},
                               "--stats");
    /* without --out the table is standard output */
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){scene, "--ply", "-", NULL},
                               "standard output");
    CHECK(access(x, F_OK) != 0); /* refused before anything was written */
    /* one existing file by two names: a hard link, a symbolic link */
    FILE *f = fopen(x, "w");
    CHECK(f != NULL);
    if (f)
        fclose(f);
    CHECK(link(x, hard) == 0);
    CHECK(symlink(x, soft) == 0);
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){scene, "--out", x, "--ply", hard, NULL},
                               "--ply");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){scene, "--png", soft, "--stats", x, NULL},
                               "--png");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){scene, "--out", x, "--stats", y, NULL},
                               "--stats");
    /* an output onto the scene itself (a copy in the test's directory) */
    char copy[512];
    snprintf(copy, sizeof copy, "%s/scene.obj", dir);
    char *text = harness_read_file(harness_path("scenes/plates_parallel/plates.obj"));
    char *strip = text ? strstr(text, "mtllib") : NULL;
    FILE *c = fopen(copy, "w");
    CHECK(text && strip && c);
    if (c) {
        /* without its material library: the scene's --rho and --emission stand in */
        for (char *line = text; text && *line; line += strcspn(line, "\n") + (line[strcspn(line, "\n")] != 0))
            if (strncmp(line, "mtllib", 6) != 0 && strncmp(line, "usemtl", 6) != 0)
                fprintf(c, "%.*s\n", (int)strcspn(line, "\n"), line);
        fclose(c);
    }
    free(text);
    char *before = harness_read_file(copy);
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){copy, "--rho", "0.5", "--emission", "1",
                                                        "--out", copy, NULL}, "scene");
    char *after = harness_read_file(copy);
    CHECK(before && after && strcmp(before, after) == 0);
    free(before);
    free(after);
    remove_dir(dir);
    free(dir);
}

TEST(outputs_written_files_replace_targets_and_leave_nothing_else)
{
    char *dir = make_dir();
    CHECK(dir != NULL);
    if (!dir)
        return;
    char paths[4][512];
    const char *names[4] = {"t.tsv", "m.ply", "i.png", "s.json"};
    for (int k = 0; k < 4; k++)
        snprintf(paths[k], sizeof paths[k], "%s/%s", dir, names[k]);
    /* an old file is replaced */
    FILE *f = fopen(paths[0], "w");
    CHECK(f != NULL);
    if (f) {
        fputs("old\n", f);
        fclose(f);
    }
    const char *args[] = {harness_path(SCENE), "--quiet", "--image-size", "16x16", "--out", paths[0],
                          "--ply", paths[1], "--png", paths[2], "--stats", paths[3], NULL};
    char *out, *err;
    CHECK(harness_radkit_run("solve", args, &out, &err) == 0);
    CHECK(strcmp(out, "") == 0);
    CHECK(count_entries(dir) == 4);
    mode_t mask = umask(0);
    umask(mask);
    for (int k = 0; k < 4; k++) {
        struct stat st;
        CHECK_MSG(stat(paths[k], &st) == 0 && st.st_size > 16, "%s missing or short", names[k]);
        CHECK_MSG((st.st_mode & 0777) == (0666 & ~mask), "%s: mode %o, want %o", names[k],
                  (unsigned)(st.st_mode & 0777), (unsigned)(0666 & ~mask));
    }
    char *text = harness_read_file(paths[0]);
    CHECK(text && strstr(text, "face\tarea\tB_r") != NULL);
    free(text);
    free(out);
    free(err);
    remove_dir(dir);
    free(dir);
}

/* compare reads tables: a directory or binary data (/dev/zero, which never
 * ends a line) is bad input, refused at once (a time limit guards the test). */
TEST(outputs_compare_refuses_directory_and_binary_tables)
{
    char *dir = make_dir();
    CHECK(dir != NULL);
    if (!dir)
        return;
    const char *scene = harness_path(SCENE);
    const char *tables[2] = {dir, "/dev/zero"};
    const char *problems[2] = {"directory", "NUL"};
    for (int k = 0; k < 2; k++) {
        const char *argv[] = {"/usr/bin/timeout", "20", harness_radkit(), "compare", scene,
                              tables[k], tables[k], NULL};
        char *out, *err;
        int code = harness_run(argv, &out, &err);
        CHECK_MSG(code == 2, "compare %s: exit %d, want 2 (%s)", tables[k], code, err);
        CHECK_MSG(strstr(err, tables[k]) && strstr(err, problems[k]), "compare %s: stderr %s",
                  tables[k], err);
        free(out);
        free(err);
    }
    remove_dir(dir);
    free(dir);
}
