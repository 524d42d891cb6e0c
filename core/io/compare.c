/* rad_io: reading a per-face table back, and the error of one table against
 * a reference, in the measures every study and test uses.
 *
 * With R = sum_f A_f sum_c (B^ref_fc - E_fc) / (3 sum_f A_f), the area-weighted
 * mean reflected radiosity of the reference (emission excluded: it is exact in
 * every method), the errors of B are
 *   l1    = sum_f A_f sum_c |B_fc - B^ref_fc| / (3 R sum_f A_f)
 *   l2    = sqrt(sum_f A_f sum_c (B_fc - B^ref_fc)^2 / (3 sum_f A_f)) / R
 *   worst = max_f max_c |B_fc - B^ref_fc| / R
 * and, for a reference with standard errors se, its own error on the same
 * scales: ref_l1 (se in place of |B - B^ref|) and ref_worst (se at the worst
 * face).  Relative to one mean, a dim face's error counts for what it adds to
 * the picture, not for its own relative size.
 *
 * The reader takes bounded lines (4094 characters) and refuses a directory
 * and binary data (a NUL byte) as bad input, so a table named /dev/zero ends
 * at its first byte instead of being read forever. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "rad_io.h"

void rad_io_faces_free(rad_io_faces *f)
{
    if (!f)
        return;
    free(f->area);
    memset(f, 0, sizeof *f);
}

/* Split a TSV line in place into at most max fields; returns the count. */
static int split_tabs(char *line, char **field, int max)
{
    int n = 0;
    char *p = line;
    while (n < max) {
        field[n++] = p;
        char *tab = strchr(p, '\t');
        if (!tab)
            break;
        *tab = '\0';
        p = tab + 1;
    }
    return n;
}

static int parse_number(const char *text, double *out)
{
    char *end = NULL;
    errno = 0;
    double v = strtod(text, &end);
    if (end == text || *end != '\0' || !isfinite(v))
        return 0;
    *out = v;
    return 1;
}

/* One line of at most size - 1 characters into buf (without its '\n'):
 * 1, or 0 at the end of the file, -1 for a longer line, -2 for a NUL byte
 * (binary data, e.g. /dev/zero: never a line end, so reading stops here). */
static int read_line(FILE *f, char *buf, size_t size, size_t *len)
{
    size_t n = 0;
    int c;
    while ((c = getc(f)) != EOF && c != '\n') {
        if (c == '\0')
            return -2;
        if (n + 1 >= size)
            return -1;
        buf[n++] = (char)c;
    }
    buf[n] = '\0';
    *len = n;
    return c == EOF && n == 0 ? 0 : 1;
}

rad_status rad_io_read_faces_tsv(const char *path, rad_io_faces *out)
{
    enum { MAX_LINE = 4096 };
    memset(out, 0, sizeof *out);
    FILE *f = fopen(path, "r");
    if (!f)
        return RAD_ERROR(RAD_EINPUT, "%s: cannot open: %s", path, strerror(errno));
    struct stat sb;
    if (fstat(fileno(f), &sb) == 0 && S_ISDIR(sb.st_mode)) {
        fclose(f);
        return RAD_ERROR(RAD_EINPUT, "%s: is a directory, not a per-face table", path);
    }
    rad_status st = RAD_OK;
    char line[MAX_LINE];
    size_t cap = 0, lineno = 0, len = 0;
    int cols = 0, got;
    double *rows = NULL; /* per row: area, B[3], se[3] */
    while ((got = read_line(f, line, sizeof line, &len)) != 0) {
        lineno++;
        if (got == -1) {
            st = RAD_ERROR(RAD_EINPUT, "%s:%zu: line longer than %d characters", path, lineno,
                           MAX_LINE - 2);
            goto done;
        }
        if (got == -2) {
            st = RAD_ERROR(RAD_EINPUT, "%s:%zu: a NUL byte: binary data, not a per-face table",
                           path, lineno);
            goto done;
        }
        while (len && line[len - 1] == '\r')
            line[--len] = '\0';
        if (line[0] == '#' || len == 0)
            continue;
        char *field[9];
        int nf = split_tabs(line, field, 9);
        if (!cols) {
            if (nf >= 5 && strcmp(field[0], "face") == 0 && strcmp(field[1], "area") == 0 &&
                strcmp(field[2], "B_r") == 0 && strcmp(field[3], "B_g") == 0 &&
                strcmp(field[4], "B_b") == 0) {
                cols = nf == 8 && strcmp(field[5], "se_r") == 0 && strcmp(field[6], "se_g") == 0 &&
                               strcmp(field[7], "se_b") == 0 ? 8 : 5;
                if (nf != cols) {
                    st = RAD_ERROR(RAD_EINPUT, "%s:%zu: unexpected columns after B_b", path, lineno);
                    goto done;
                }
                continue;
            }
            st = RAD_ERROR(RAD_EINPUT, "%s:%zu: expected the header row 'face area B_r B_g B_b'",
                           path, lineno);
            goto done;
        }
        double v[8];
        if (nf != cols) {
            st = RAD_ERROR(RAD_EINPUT, "%s:%zu: %d columns, the header has %d", path, lineno, nf,
                           cols);
            goto done;
        }
        for (int k = 0; k < nf; k++)
            if (!parse_number(field[k], &v[k])) {
                st = RAD_ERROR(RAD_EINPUT, "%s:%zu: column %d: '%s' is not a finite number", path,
                               lineno, k + 1, field[k]);
                goto done;
            }
        if (v[0] != (double)out->n) {
            st = RAD_ERROR(RAD_EINPUT, "%s:%zu: face %g out of order (expected %zu)", path,
                           lineno, v[0], out->n);
            goto done;
        }
        if (out->n == cap) {
            cap = cap ? 2 * cap : 64;
            double *grown = realloc(rows, cap * 7 * sizeof *rows);
            if (!grown) {
                st = RAD_ERROR(RAD_ENOMEM, "%s: no memory for %zu rows", path, cap);
                goto done;
            }
            rows = grown;
        }
        double *r = rows + 7 * out->n;
        for (int k = 0; k < 7; k++)
            r[k] = k + 1 < nf ? v[k + 1] : 0.0;
        out->n++;
    }
    if (ferror(f)) {
        st = RAD_ERROR(RAD_EIO, "%s: read error: %s", path, strerror(errno));
        goto done;
    }
    if (!cols || out->n == 0) {
        st = RAD_ERROR(RAD_EINPUT, "%s: no per-face table in the file", path);
        goto done;
    }
    size_t n = out->n;
    out->area = malloc(n * 7 * sizeof *out->area);
    if (!out->area) {
        st = RAD_ERROR(RAD_ENOMEM, "%s: no memory for %zu faces", path, n);
        goto done;
    }
    out->B = out->area + n;
    out->se = cols == 8 ? out->area + 4 * n : NULL;
    for (size_t i = 0; i < n; i++) {
        out->area[i] = rows[7 * i];
        for (int c = 0; c < 3; c++) {
            out->B[i + c * n] = rows[7 * i + 1 + c];
            out->area[4 * n + i + c * n] = rows[7 * i + 4 + c];
        }
    }
done:
    free(rows);
    fclose(f);
    if (st != RAD_OK) {
        free(out->area);
        memset(out, 0, sizeof *out);
    }
    return st;
}

rad_status rad_io_face_error(size_t n, const double *area, const double *E, const double *B,
                             const double *B_ref, const double *se_ref, rad_io_face_errors *out)
{
    memset(out, 0, sizeof *out);
    out->worst_face = -1;
    double total = 0.0, reflected = 0.0;
    for (size_t i = 0; i < n; i++) {
        total += area[i];
        for (int c = 0; c < 3; c++)
            reflected += area[i] * (B_ref[i + c * n] - (E ? E[i + c * n] : 0.0));
    }
    if (!(total > 0.0))
        return RAD_ERROR(RAD_EINPUT, "face error: the faces have no area");
    double R = reflected / (3.0 * total);
    if (!(R > 0.0))
        return RAD_ERROR(RAD_EINPUT, "face error: the reference reflects nothing (mean reflected "
                                     "radiosity %g), so no relative error is defined", R);
    double l1 = 0.0, l2 = 0.0, ref = 0.0, worst = -1.0, P = 0.0, P_ref = 0.0;
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++) {
            double d = fabs(B[i + c * n] - B_ref[i + c * n]);
            if (!isfinite(d))
                return RAD_ERROR(RAD_EINPUT, "face error: face %zu has a non-finite radiosity", i);
            l1 += area[i] * d;
            l2 += area[i] * d * d;
            P += area[i] * B[i + c * n];
            P_ref += area[i] * B_ref[i + c * n];
            if (se_ref)
                ref += area[i] * se_ref[i + c * n];
            if (d > worst) {
                worst = d;
                out->worst_face = (int)i;
                out->ref_worst = se_ref ? se_ref[i + c * n] / R : 0.0;
            }
        }
    out->mean_reflected = R;
    out->l1 = l1 / (3.0 * total * R);
    out->l2 = sqrt(l2 / (3.0 * total)) / R;
    out->worst = worst / R;
    out->ref_l1 = ref / (3.0 * total * R);
    out->power = P_ref > 0.0 ? (P - P_ref) / P_ref : 0.0;
    return RAD_OK;
}
