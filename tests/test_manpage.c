/* The manual page (scripts/manpage.sh, generated from the program's --help
 * texts): it names every option any command's --help names, has a section
 * per command, and groff renders it without a warning. */
#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "harness.h"

/* Generate the page from the binary under test; NULL on failure. */
static char *manpage_source(void)
{
    char *out, *err;
    const char *argv[] = {"/bin/sh", harness_path("scripts/manpage.sh"), harness_radkit(), NULL};
    int code = harness_run(argv, &out, &err);
    CHECK_MSG(code == 0 && err[0] == '\0', "manpage.sh: exit %d, stderr: %s", code, err);
    free(err);
    if (code != 0) {
        free(out);
        return NULL;
    }
    return out;
}

/* Render with groff as man does (-man, ASCII, no overstriking), every
 * warning on.  Returns the text (NULL if groff is missing); *warnings gets
 * groff's stderr. */
static char *manpage_render(const char *source, char **warnings)
{
    char path[] = "/tmp/radkit-test-man-XXXXXX";
    int fd = mkstemp(path);
    CHECK(fd >= 0);
    if (fd < 0)
        return NULL;
    size_t len = strlen(source);
    CHECK(write(fd, source, len) == (ssize_t)len);
    close(fd);
    char *out;
    const char *argv[] = {"/bin/sh", "-c",
                          "command -v groff >/dev/null || exit 99; "
                          "exec groff -man -Tascii -ww -P-cbou \"$1\"",
                          "sh", path, NULL};
    int code = harness_run(argv, &out, warnings);
    unlink(path);
    if (code == 99) {
        free(out);
        return NULL;
    }
    CHECK_MSG(code == 0, "groff exit %d: %s", code, *warnings);
    return out;
}

/* 1 when `word` occurs in text not inside a longer option name. */
static int has_word(const char *text, const char *word)
{
    size_t n = strlen(word);
    for (const char *p = strstr(text, word); p; p = strstr(p + 1, word)) {
        int before = p > text && (isalnum((unsigned char)p[-1]) || p[-1] == '-');
        int after = isalnum((unsigned char)p[n]) || p[n] == '-' || p[n] == '_';
        if (!before && !after)
            return 1;
    }
    return 0;
}

/* Every "--name" in a help text, appended to list (count in *n). */
static void collect_options(const char *help, char list[][48], int *n, int max)
{
    for (const char *p = strstr(help, "--"); p; p = strstr(p + 2, "--")) {
        if (p > help && (isalnum((unsigned char)p[-1]) || p[-1] == '-'))
            continue;
        size_t len = 2;
        while (isalnum((unsigned char)p[len]) || p[len] == '-')
            len++;
        if (len == 2 || len >= 48)
            continue;
        int seen = 0;
        for (int k = 0; k < *n && !seen; k++)
            seen = strncmp(list[k], p, len) == 0 && list[k][len] == '\0';
        if (!seen && *n < max) {
            memcpy(list[*n], p, len);
            list[(*n)++][len] = '\0';
        }
    }
}

TEST(manpage_names_every_option_and_renders_cleanly)
{
    char *source = manpage_source();
    if (!source)
        return;
    char *top, *err;
    CHECK(harness_radkit_run(NULL, (const char *[]){"--help", NULL}, &top, &err) == 0);
    free(err);

    /* The commands are the indented words under "commands:" in --help. */
    char commands[16][32], options[256][48];
    int ncommands = 0, noptions = 0;
    const char *p = strstr(top, "\ncommands:\n");
    CHECK(p != NULL);
    for (p = p ? strchr(p + 1, '\n') + 1 : NULL; p && strncmp(p, "  ", 2) == 0 && ncommands < 16;
         p = strchr(p, '\n') + 1) {
        if (p[2] != ' ' && sscanf(p, "%31s", commands[ncommands]) == 1)
            ncommands++;
    }
    CHECK_MSG(ncommands >= 5, "%d commands under 'commands:' in radkit --help", ncommands);
    collect_options(top, options, &noptions, 256);
    for (int c = 0; c < ncommands; c++) {
        char *help;
        CHECK_MSG(harness_radkit_run(commands[c], (const char *[]){"--help", NULL}, &help, &err) == 0,
                  "radkit %s --help failed", commands[c]);
        collect_options(help, options, &noptions, 256);
        char section[64];
        snprintf(section, sizeof section, "\n.SS %s\n", commands[c]);
        CHECK_MSG(strstr(source, section) != NULL, "no section for %s in the man page", commands[c]);
        free(help);
        free(err);
    }
    /* galerkin1d, info, ff, solve and compare have some 60 options between them. */
    CHECK_MSG(noptions > 40, "only %d options found in the --help texts", noptions);

    char *warnings = NULL;
    char *text = manpage_render(source, &warnings);
    if (text) {
        CHECK_MSG(warnings[0] == '\0', "groff warns: %s", warnings);
        for (int k = 0; k < noptions; k++)
            CHECK_MSG(has_word(text, options[k]), "the man page does not mention %s", options[k]);
        CHECK(strstr(text, "SCENE OPTIONS") != NULL);
    } else {
        /* No groff: check the source, where '-' is written '\-'. */
        fprintf(stderr, "manpage: groff not installed; checking the troff source only\n");
        for (int k = 0; k < noptions; k++) {
            char escaped[128] = "";
            for (const char *q = options[k]; *q; q++)
                strncat(escaped, *q == '-' ? "\\-" : (char[]){*q, '\0'}, sizeof escaped - strlen(escaped) - 1);
            CHECK_MSG(strstr(source, escaped) != NULL, "the man page does not mention %s", options[k]);
        }
    }
    free(text);
    free(warnings);
    free(top);
    free(source);
}

/* The page's name line and header come from the program: its version. */
TEST(manpage_carries_the_program_version)
{
    char *source = manpage_source(), *version, *err;
    if (!source)
        return;
    CHECK(harness_radkit_run(NULL, (const char *[]){"--version", NULL}, &version, &err) == 0);
    version[strcspn(version, "\n")] = '\0';
    char th[128];
    snprintf(th, sizeof th, ".TH RADKIT 1 \"\" \"%s\"", version);
    CHECK_MSG(strstr(source, th) != NULL, "no '%s' line", th);
    CHECK(strstr(source, "\n.SH NAME\nradkit \\- ") != NULL);
    free(source);
    free(version);
    free(err);
}
