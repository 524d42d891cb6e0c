/* Import through Assimp's C API: glTF 2.0, STL and the other formats Assimp
 * reads [assimp], except OBJ, OFF and PLY, which radkit reads itself
 * (import_obj.c, import_off.c, import_ply.c): Assimp's OFF and PLY readers
 * lose faces, hang on a PLY header without end_header and invent data where a
 * file is shorter than its header says.  STL loads every facet of the
 * libcgal-demo corpus (tests/test_corpus.c).
 *
 *  1. aiImportFileExWithProperties with aiProcess_JoinIdenticalVertices
 *     (shared corners) and aiProcess_ValidateDataStructure (indices in range).
 *     Deliberately NOT aiProcess_FindDegenerates (it would drop zero-area
 *     faces silently; validation must see them), nor aiProcess_SortByPType or
 *     aiProcess_PreTransformVertices (they regroup meshes and lose the input
 *     order), nor aiProcess_Triangulate: polygons are fan-triangulated here, so
 *     that every triangle knows its input face (scene_finish refuses a
 *     polygon the fan would fold, i.e. a non-convex one; radkit's own
 *     readers ear-clip those through scene_add_polygon).
 *  2. Walk the node tree depth first, children in order, each node's meshes in
 *     order, applying the accumulated node transform in double precision:
 *     the triangles come out in the order of the file's meshes and faces.
 *     Point and line primitives are skipped with a warning.
 *  3. Materials: glTF's baseColorFactor ($clr.base, or $clr.diffuse) is the
 *     reflectance and emissiveFactor ($clr.emissive) times
 *     KHR_materials_emissive_strength ($mat.emissiveIntensity) the emission.
 *     STL carries no usable material: every face gets one material from the
 *     parameters (--rho, --emission; default grey 0.5, no emission).
 *     Other formats: Assimp's diffuse and emissive colours.
 *  4. The first camera, if any, placed by its node's transform.
 * Coordinates pass through Assimp's single precision (ai_real is float in
 * Debian's build): glTF and binary STL carry float32 data already; ASCII STL
 * is rounded to about 7 digits. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <assimp/cimport.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include "rad_geom.h"
#include "scene_internal.h"

static const unsigned import_flags = aiProcess_JoinIdenticalVertices | aiProcess_ValidateDataStructure;

static int has_extension(const char *path, const char *ext)
{
    size_t n = strlen(path), e = strlen(ext);
    if (n < e)
        return 0;
    for (size_t i = 0; i < e; i++) {
        char c = path[n - e + i];
        if (c >= 'A' && c <= 'Z')
            c = (char)(c - 'A' + 'a');
        if (c != ext[i])
            return 0;
    }
    return 1;
}

typedef struct xform {
    double m[4][4];
} xform;

static xform xform_of(const struct aiMatrix4x4 *a)
{
    const ai_real *r = &a->a1; /* row-major a1..a4, b1..b4, ... */
    xform x;
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            x.m[i][j] = (double)r[4 * i + j];
    return x;
}

static xform xform_mul(const xform *a, const xform *b)
{
    xform x;
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) {
            double s = 0.0;
            for (int k = 0; k < 4; k++)
                s += a->m[i][k] * b->m[k][j];
            x.m[i][j] = s;
        }
    return x;
}

static void xform_point(const xform *x, const double in[3], double w, double out[3])
{
    for (int i = 0; i < 3; i++)
        out[i] = x->m[i][0] * in[0] + x->m[i][1] * in[1] + x->m[i][2] * in[2] + x->m[i][3] * w;
}

typedef struct walk {
    rad_scene *s;
    const struct aiScene *ai;
    int material_base; /* scene material index of Assimp material 0, or -1: one material */
    int single_material;
    int faces;         /* input faces so far */
    int skipped;       /* point / line primitives */
} walk;

static rad_status add_mesh(walk *w, const struct aiMesh *mesh, const xform *x)
{
    int base = w->s->nv;
    rad_status st = RAD_OK;
    for (unsigned v = 0; v < mesh->mNumVertices && st == RAD_OK; v++) {
        double p[3] = {mesh->mVertices[v].x, mesh->mVertices[v].y, mesh->mVertices[v].z}, q[3];
        xform_point(x, p, 1.0, q);
        st = scene_add_vertex(w->s, q[0], q[1], q[2]);
    }
    int mat = w->single_material >= 0 ? w->single_material
                                      : w->material_base + (int)mesh->mMaterialIndex;
    for (unsigned f = 0; f < mesh->mNumFaces && st == RAD_OK; f++) {
        const struct aiFace *face = &mesh->mFaces[f];
        if (face->mNumIndices < 3) {
            w->skipped++;
            continue;
        }
        for (unsigned k = 2; k < face->mNumIndices && st == RAD_OK; k++)
            st = scene_add_triangle(w->s, base + (int)face->mIndices[0], base + (int)face->mIndices[k - 1],
                                    base + (int)face->mIndices[k], mat, w->faces, 0);
        w->faces++;
    }
    return st;
}

static rad_status walk_node(walk *w, const struct aiNode *node, const xform *parent)
{
    xform local = xform_of(&node->mTransformation), global = xform_mul(parent, &local);
    rad_status st = RAD_OK;
    for (unsigned i = 0; i < node->mNumMeshes && st == RAD_OK; i++) {
        unsigned m = node->mMeshes[i];
        if (m < w->ai->mNumMeshes)
            st = add_mesh(w, w->ai->mMeshes[m], &global);
    }
    for (unsigned c = 0; c < node->mNumChildren && st == RAD_OK; c++)
        st = walk_node(w, node->mChildren[c], &global);
    return st;
}

static const struct aiNode *find_node(const struct aiNode *node, const struct aiString *name,
                                      const xform *parent, xform *out)
{
    xform local = xform_of(&node->mTransformation), global = xform_mul(parent, &local);
    if (node->mName.length == name->length && strcmp(node->mName.data, name->data) == 0) {
        *out = global;
        return node;
    }
    for (unsigned c = 0; c < node->mNumChildren; c++) {
        const struct aiNode *hit = find_node(node->mChildren[c], name, &global, out);
        if (hit)
            return hit;
    }
    return NULL;
}

static void read_camera(rad_scene *s, const struct aiScene *ai)
{
    if (ai->mNumCameras == 0 || !ai->mRootNode)
        return;
    const struct aiCamera *cam = ai->mCameras[0];
    xform id = {{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}}, x;
    if (!find_node(ai->mRootNode, &cam->mName, &id, &x))
        x = id;
    double pos[3] = {cam->mPosition.x, cam->mPosition.y, cam->mPosition.z};
    double dir[3] = {cam->mLookAt.x, cam->mLookAt.y, cam->mLookAt.z};
    double up[3] = {cam->mUp.x, cam->mUp.y, cam->mUp.z}, d[3];
    xform_point(&x, pos, 1.0, s->camera.position);
    xform_point(&x, dir, 0.0, d);
    xform_point(&x, up, 0.0, s->camera.up);
    for (int k = 0; k < 3; k++)
        s->camera.look_at[k] = s->camera.position[k] + d[k];
    /* Assimp keeps half the horizontal angle; the vertical one follows from the aspect. */
    double half_h = cam->mHorizontalFOV, aspect = cam->mAspect > 0 ? cam->mAspect : 1.0;
    double fov = 2.0 * atan(tan(half_h) / aspect) * (180.0 / RAD_PI);
    s->camera.fov_y_deg = fov > 0.0 && fov < 180.0 ? fov : 40.0;
    s->camera.from_scene = 1;
}

static rad_status read_materials(rad_scene *s, const struct aiScene *ai, const char *path, int gltf)
{
    rad_status st = RAD_OK;
    enum { MAX_STRENGTHS = 4096 };
    static _Thread_local double strength[MAX_STRENGTHS];
    int nstrength = gltf ? scene_gltf_emissive_strengths(path, strength, MAX_STRENGTHS) : 0;
    for (unsigned m = 0; m < ai->mNumMaterials && st == RAD_OK; m++) {
        const struct aiMaterial *mat = ai->mMaterials[m];
        struct aiString name;
        struct aiColor4D c;
        double rho[3] = {0.5, 0.5, 0.5}, e[3] = {0, 0, 0};
        if (aiGetMaterialString(mat, AI_MATKEY_NAME, &name) != aiReturn_SUCCESS)
            snprintf(name.data, sizeof name.data, "material%u", m);
        if ((gltf && aiGetMaterialColor(mat, AI_MATKEY_BASE_COLOR, &c) == aiReturn_SUCCESS) ||
            aiGetMaterialColor(mat, AI_MATKEY_COLOR_DIFFUSE, &c) == aiReturn_SUCCESS) {
            rho[0] = c.r;
            rho[1] = c.g;
            rho[2] = c.b;
        }
        if (aiGetMaterialColor(mat, AI_MATKEY_COLOR_EMISSIVE, &c) == aiReturn_SUCCESS) {
            e[0] = c.r;
            e[1] = c.g;
            e[2] = c.b;
        }
        ai_real intensity = 1;
        unsigned one = 1;
        if (aiGetMaterialFloatArray(mat, AI_MATKEY_EMISSIVE_INTENSITY, &intensity, &one) ==
            aiReturn_SUCCESS) {
            for (int k = 0; k < 3; k++)
                e[k] *= (double)intensity;
        } else if ((int)m < nstrength) {
            /* Debian's Assimp ignores KHR_materials_emissive_strength: read it here. */
            for (int k = 0; k < 3; k++)
                e[k] *= strength[m];
        }
        st = scene_add_material(s, name.data, rho, e);
    }
    return st;
}

rad_status scene_import_assimp(rad_scene *s, const char *path, const rad_scene_params *p)
{
    struct aiPropertyStore *props = aiCreatePropertyStore();
    const struct aiScene *ai = aiImportFileExWithProperties(path, import_flags, NULL, props);
    aiReleasePropertyStore(props);
    if (!ai)
        return RAD_ERROR(RAD_EINPUT, "%s: cannot read the scene: %s", path, aiGetErrorString());
    rad_status st = RAD_OK;
    int gltf = has_extension(path, ".gltf") || has_extension(path, ".glb");
    int geometry_only = has_extension(path, ".stl");
    walk w = {s, ai, 0, -1, 0, 0};
    if (geometry_only || ai->mNumMaterials == 0) {
        double zero[3] = {0, 0, 0};
        st = scene_add_material(s, "default", p->default_rho, zero);
        w.single_material = 0;
    } else {
        st = read_materials(s, ai, path, gltf);
    }
    xform id = {{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}};
    if (st == RAD_OK && ai->mRootNode)
        st = walk_node(&w, ai->mRootNode, &id);
    if (st == RAD_OK && w.skipped > 0)
        st = scene_warn(s, "skipped %d point or line primitive(s)", w.skipped);
    if (st == RAD_OK)
        read_camera(s, ai);
    aiReleaseImport(ai);
    return st;
}

rad_status scene_assimp_count(const char *path, long *triangles, long *materials)
{
    const struct aiScene *ai = aiImportFile(path, import_flags);
    if (!ai)
        return RAD_ERROR(RAD_EDEP, "%s", aiGetErrorString());
    long n = 0;
    for (unsigned m = 0; m < ai->mNumMeshes; m++)
        for (unsigned f = 0; f < ai->mMeshes[m]->mNumFaces; f++)
            if (ai->mMeshes[m]->mFaces[f].mNumIndices >= 3)
                n += (long)ai->mMeshes[m]->mFaces[f].mNumIndices - 2;
    *triangles = n;
    *materials = (long)ai->mNumMaterials;
    aiReleaseImport(ai);
    return RAD_OK;
}
