/* The OBJ reader's numbers are strtod's, bit for bit: plain decimals take a
 * shorter path (one correctly rounded division), every other form strtod
 * itself, and the coordinates a scene loads are the ones strtod reads from
 * the file's text, whichever path read them. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "rad_scene.h"

static unsigned long long next(unsigned long long *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return *s >> 33;
}

/* A random number token: a sign or none, 0-3 integer digits (leading zeros
 * at times), a point and 0-26 fraction digits, now and then an exponent
 * (strtod's path): both sides of the short path's limits, 19 significant
 * digits and 22 after the point. */
static void random_token(unsigned long long *s, char *out)
{
    char *c = out;
    unsigned long long r = next(s);
    if (r % 3 == 0)
        *c++ = '-';
    else if (r % 7 == 1)
        *c++ = '+';
    int whole = (int)(next(s) % 4), frac = (int)(next(s) % 27);
    if (whole == 0 && frac == 0)
        whole = 1;
    for (int k = 0; k < whole; k++)
        *c++ = (char)('0' + (k == 0 && next(s) % 4 == 0 ? 0 : next(s) % 10));
    if (frac > 0 || next(s) % 5 == 0) {
        *c++ = '.';
        for (int k = 0; k < frac; k++)
            *c++ = (char)('0' + next(s) % 10);
    }
    if (next(s) % 11 == 0)
        c += sprintf(c, "e%d", (int)(next(s) % 7) - 3);
    *c = '\0';
}

TEST(obj_coordinates_are_strtods_bit_for_bit)
{
    enum { TRIS = 3000 };
    const size_t token = 48;
    char *tokens = malloc((size_t)TRIS * 9 * token);
    char *text = malloc((size_t)TRIS * (9 * token + 64));
    if (!tokens || !text) {
        CHECK(0);
        free(tokens);
        free(text);
        return;
    }
    unsigned long long s = 12345;
    char *w = text;
    for (int t = 0; t < TRIS; t++)
        for (int v = 0; v < 3; v++) {
            w += sprintf(w, "v");
            for (int a = 0; a < 3; a++) {
                char *tok = tokens + ((size_t)(9 * t + 3 * v + a)) * token;
                random_token(&s, tok);
                w += sprintf(w, " %s", tok);
            }
            w += sprintf(w, "\n");
        }
    for (int t = 0; t < TRIS; t++)
        w += sprintf(w, "f %d %d %d\n", 3 * t + 1, 3 * t + 2, 3 * t + 3);
    const char *obj = harness_write_file("numbers.obj", text);
    rad_scene *scene = NULL;
    CHECK_MSG(rad_scene_load(obj, NULL, &scene) == RAD_OK, "%s", rad_error_message());
    if (scene) {
        const double *xyz = rad_scene_vertices(scene);
        const int *tri = rad_scene_triangles(scene), *face = rad_scene_triangle_faces(scene);
        int n = rad_scene_triangle_count(scene), differ = 0, kept = 0;
        for (int k = 0; k < n; k++) {
            int t = face[k];
            if (t < 0 || t >= TRIS)
                continue;
            kept++;
            for (int v = 0; v < 3; v++)
                for (int a = 0; a < 3; a++) {
                    const char *tok = tokens + ((size_t)(9 * t + 3 * v + a)) * token;
                    double want = strtod(tok, NULL), got = xyz[3 * tri[3 * k + v] + a];
                    if (memcmp(&want, &got, sizeof want) != 0 && differ++ < 3)
                        fprintf(stderr, "# '%s': strtod %.17g, loaded %.17g\n", tok, want, got);
                }
        }
        CHECK_MSG(differ == 0, "%d coordinates differ from strtod's", differ);
        CHECK_MSG(kept > TRIS * 9 / 10, "only %d of %d triangles loaded", kept, TRIS);
    }
    rad_scene_destroy(scene);
    remove(obj);
    free(tokens);
    free(text);
}
