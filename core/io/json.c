/* A small JSON emitter and the stats file of `solve --stats`.
 * Strings are escaped per RFC 8259 (quote, backslash, control characters as
 * \uXXXX); numbers use %.17g and must be finite (JSON has no NaN or Inf):
 * a non-finite number is an error naming its key, never a silent null.
 * The stats file is written through rad_io_output: whole or not at all. */
#include "rad_io.h"

#include <errno.h>
#include <math.h>
#include <string.h>

static void put_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (const unsigned char *p = (const unsigned char *)s; *p; p++) {
        switch (*p) {
        case '"': fputs("\\\"", f); break;
        case '\\': fputs("\\\\", f); break;
        case '\n': fputs("\\n", f); break;
        case '\r': fputs("\\r", f); break;
        case '\t': fputs("\\t", f); break;
        default:
            if (*p < 0x20)
                fprintf(f, "\\u%04x", *p);
            else
                fputc(*p, f);
        }
    }
    fputc('"', f);
}

/* Comma, newline, indentation and the key of the next member. */
static int member(rad_io_json *j, const char *key)
{
    if (j->status != RAD_OK)
        return 0;
    if (j->depth < 1) {
        j->status = RAD_ERROR(RAD_EINVAL, "JSON: member '%s' outside any object", key ? key : "");
        return 0;
    }
    if (!key) {
        j->status = RAD_ERROR(RAD_EINVAL, "JSON: object member without a key");
        return 0;
    }
    fputs(j->first[j->depth - 1] ? "\n" : ",\n", j->f);
    j->first[j->depth - 1] = 0;
    for (int d = 0; d < j->depth; d++)
        fputs("  ", j->f);
    put_string(j->f, key);
    fputs(": ", j->f);
    return 1;
}

void rad_io_json_start(rad_io_json *j, FILE *f)
{
    j->f = f;
    j->depth = 1;
    j->first[0] = 1;
    j->status = f ? RAD_OK : RAD_ERROR(RAD_EINVAL, "JSON: no file");
    if (f)
        fputc('{', f);
}

void rad_io_json_object(rad_io_json *j, const char *key)
{
    if (j->status == RAD_OK && j->depth >= (int)(sizeof j->first / sizeof j->first[0])) {
        j->status = RAD_ERROR(RAD_EINVAL, "JSON: nesting deeper than %d", j->depth);
        return;
    }
    if (!member(j, key))
        return;
    fputc('{', j->f);
    j->first[j->depth++] = 1;
}

void rad_io_json_end(rad_io_json *j)
{
    if (j->status != RAD_OK)
        return;
    if (j->depth < 1) {
        j->status = RAD_ERROR(RAD_EINVAL, "JSON: more closing braces than objects");
        return;
    }
    j->depth--;
    if (!j->first[j->depth]) {
        fputc('\n', j->f);
        for (int d = 0; d < j->depth; d++)
            fputs("  ", j->f);
    }
    fputc('}', j->f);
}

void rad_io_json_string(rad_io_json *j, const char *key, const char *value)
{
    if (member(j, key))
        put_string(j->f, value ? value : "");
}

void rad_io_json_number(rad_io_json *j, const char *key, double value)
{
    if (j->status == RAD_OK && !isfinite(value)) {
        j->status = RAD_ERROR(RAD_ENUMERIC, "JSON: key '%s' has the non-finite value %g",
                              key ? key : "", value);
        return;
    }
    if (member(j, key))
        fprintf(j->f, "%.17g", value);
}

void rad_io_json_integer(rad_io_json *j, const char *key, long long value)
{
    if (member(j, key))
        fprintf(j->f, "%lld", value);
}

rad_status rad_io_json_finish(rad_io_json *j)
{
    if (j->status == RAD_OK && j->depth != 1)
        j->status = RAD_ERROR(RAD_EINVAL, "JSON: %d objects left open", j->depth - 1);
    if (j->status == RAD_OK) {
        rad_io_json_end(j);
        fputc('\n', j->f);
    }
    return j->status;
}

rad_status rad_io_write_stats_json(const char *path, const rad_io_stats *s)
{
    if (!path || !s)
        return RAD_ERROR(RAD_EINVAL, "stats JSON: NULL argument");
    rad_io_output o;
    rad_status status = rad_io_output_open(path, 0, &o);
    if (status != RAD_OK)
        return status;
    FILE *f = o.f;
    rad_io_json j;
    rad_io_json_start(&j, f);
    rad_io_json_string(&j, "method", s->method);
    rad_io_json_integer(&j, "faces", s->faces);
    rad_io_json_integer(&j, "elements", s->elements);
    rad_io_json_integer(&j, "links", s->links);
    rad_io_json_integer(&j, "rays", s->rays);
    rad_io_json_integer(&j, "kernel_evals", s->kernel_evals);
    rad_io_json_object(&j, "time_s");
    for (size_t k = 0; k < s->nphases; k++)
        rad_io_json_number(&j, s->phases[k].name, s->phases[k].seconds);
    rad_io_json_number(&j, "total", s->total_seconds);
    rad_io_json_end(&j);
    rad_io_json_number(&j, "memory_peak_bytes", s->memory_peak_bytes);
    if (s->ranks > 0) {
        rad_io_json_integer(&j, "ranks", s->ranks);
        rad_io_json_number(&j, "memory_peak_bytes_per_rank", s->memory_peak_bytes_per_rank);
    }
    rad_io_json_object(&j, "effects");
    for (size_t k = 0; k < s->neffects; k++) {
        rad_io_json_object(&j, s->effects[k].name);
        rad_io_json_string(&j, "value", s->effects[k].value);
        rad_io_json_string(&j, "reason", s->effects[k].reason);
        rad_io_json_end(&j);
    }
    rad_io_json_end(&j);
    rad_io_json_object(&j, "solver");
    rad_io_json_string(&j, "name", s->solver_name);
    rad_io_json_integer(&j, "iterations", s->solver_iterations);
    rad_io_json_number(&j, "residual", s->solver_residual);
    rad_io_json_end(&j);
    if (s->ndetails) {
        rad_io_json_object(&j, "details");
        for (size_t k = 0; k < s->ndetails; k++)
            rad_io_json_number(&j, s->details[k].name, s->details[k].value);
        rad_io_json_end(&j);
    }
    status = rad_io_json_finish(&j);
    if (status != RAD_OK) {
        rad_io_output_discard(&o); /* no half-written JSON: the target stays as it was */
        return status;
    }
    return rad_io_output_commit(&o);
}
