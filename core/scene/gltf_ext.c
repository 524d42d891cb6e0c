/* glTF 2.0 material extensions that Debian's Assimp (5.2) does not import:
 * KHR_materials_emissive_strength [gltf:emissive_strength].
 *
 * The emission of a glTF material is emissiveFactor times emissiveStrength
 * (default 1).  Assimp gives the factor; this file reads the strength of each
 * material straight from the glTF JSON (a .gltf file, or the JSON chunk of a
 * .glb), with a small JSON walker:
 *  1. Load the JSON text (for .glb: the first chunk, type "JSON").
 *  2. Find the top-level "materials" array and, in each element, the path
 *     extensions / KHR_materials_emissive_strength / emissiveStrength.
 *  3. Return one strength per material, in the array's order, which is the
 *     order of Assimp's materials for glTF. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene_internal.h"

static const char *ws(const char *p, const char *end)
{
    while (p < end && (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r'))
        p++;
    return p;
}

/* Skip a string starting at '"'; return the position after it (NULL if bad). */
static const char *skip_string(const char *p, const char *end)
{
    if (p >= end || *p != '"')
        return NULL;
    for (p++; p < end; p++) {
        if (*p == '\\')
            p++;
        else if (*p == '"')
            return p + 1;
    }
    return NULL;
}

/* Skip any JSON value; NULL on malformed input or too deep nesting. */
static const char *skip_value(const char *p, const char *end, int depth)
{
    p = ws(p, end);
    if (p >= end || depth > 64)
        return NULL;
    if (*p == '"')
        return skip_string(p, end);
    if (*p == '{' || *p == '[') {
        char close = *p == '{' ? '}' : ']';
        p = ws(p + 1, end);
        if (p < end && *p == close)
            return p + 1;
        for (;;) {
            if (close == '}') {
                p = skip_string(ws(p, end), end);
                if (!p)
                    return NULL;
                p = ws(p, end);
                if (p >= end || *p != ':')
                    return NULL;
                p++;
            }
            p = skip_value(p, end, depth + 1);
            if (!p)
                return NULL;
            p = ws(p, end);
            if (p < end && *p == ',') {
                p++;
                continue;
            }
            return p < end && *p == close ? p + 1 : NULL;
        }
    }
    while (p < end && *p != ',' && *p != '}' && *p != ']' && *p != ' ' && *p != '\n' &&
           *p != '\r' && *p != '\t')
        p++;
    return p;
}

/* In the object at p ('{'), the value of member `key` (NULL if absent). */
static const char *member(const char *p, const char *end, const char *key)
{
    p = ws(p, end);
    if (p >= end || *p != '{')
        return NULL;
    p = ws(p + 1, end);
    size_t klen = strlen(key);
    while (p < end && *p == '"') {
        const char *name = p + 1, *after = skip_string(p, end);
        if (!after)
            return NULL;
        p = ws(after, end);
        if (p >= end || *p != ':')
            return NULL;
        p = ws(p + 1, end);
        if ((size_t)(after - 1 - name) == klen && memcmp(name, key, klen) == 0)
            return p;
        p = skip_value(p, end, 0);
        if (!p)
            return NULL;
        p = ws(p, end);
        if (p < end && *p == ',')
            p = ws(p + 1, end);
    }
    return NULL;
}

static char *read_json(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    char *buf = NULL;
    size_t cap = 0, n = 0;
    for (;;) {
        if (n + 4096 > cap) {
            size_t next = cap ? 2 * cap : 65536;
            char *q = realloc(buf, next);
            if (!q) {
                free(buf);
                fclose(f);
                return NULL;
            }
            buf = q;
            cap = next;
        }
        size_t got = fread(buf + n, 1, cap - n, f);
        n += got;
        if (got == 0)
            break;
    }
    fclose(f);
    /* A .glb: 12-byte header "glTF", then chunk 0 (length, type "JSON"). */
    if (n >= 20 && memcmp(buf, "glTF", 4) == 0) {
        uint32_t clen = (uint32_t)(unsigned char)buf[12] | (uint32_t)(unsigned char)buf[13] << 8 |
                        (uint32_t)(unsigned char)buf[14] << 16 | (uint32_t)(unsigned char)buf[15] << 24;
        if (memcmp(buf + 16, "JSON", 4) != 0 || (size_t)clen > n - 20) {
            free(buf);
            return NULL;
        }
        memmove(buf, buf + 20, clen);
        n = clen;
    }
    *len = n;
    return buf;
}

int scene_gltf_emissive_strengths(const char *path, double *strength, int cap)
{
    size_t len = 0;
    char *json = read_json(path, &len);
    if (!json)
        return 0;
    const char *end = json + len;
    const char *mats = member(json, end, "materials");
    int count = 0;
    if (mats && *mats == '[') {
        const char *p = ws(mats + 1, end);
        while (p && p < end && *p == '{' && count < cap) {
            double s = 1.0;
            const char *ext = member(p, end, "extensions");
            const char *k = ext ? member(ext, end, "KHR_materials_emissive_strength") : NULL;
            const char *v = k ? member(k, end, "emissiveStrength") : NULL;
            if (v) {
                char *stop = NULL;
                double x = strtod(v, &stop);
                if (stop != v)
                    s = x;
            }
            strength[count++] = s;
            p = skip_value(p, end, 0);
            p = p ? ws(p, end) : NULL;
            if (p && p < end && *p == ',')
                p = ws(p + 1, end);
        }
    }
    free(json);
    return count;
}
