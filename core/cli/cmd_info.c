/* radkit info: load and validate a scene, print its figures, adjacency,
 * closedness and convexity, and the effects plan with reasons. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "rad_geom.h"
#include "rad_mesh.h"
#include "rad_scene.h"
#include "rad_version.h"

static const char help_head[] =
    "usage: radkit info SCENE [--assimp-check] [--scale S] [--strict] [--rho \"r g b\"]\n"
    "                         [--emission \"r g b\"] [--curve-tol T] [--occlusion M]\n"
    "                         [--colour M] [--facing-away M] [--singular M]\n"
    "                         [--reflectance M]\n"
    "\n"
    "Load SCENE (OBJ+MTL, MGF, glTF 2.0, PLY, OFF, STL), validate it and report it.\n"
    "\n"
    "  --assimp-check     OBJ: also read the file with Assimp and warn when its\n"
    "                     triangle count differs (an independent reader; it runs\n"
    "                     in this process and can crash on malformed files,\n"
    "                     e.g. a material statement before any newmtl)\n"
    ;

static const char help_tail[] =
    "\n"
    "Output: '# key = value' lines: the counts (faces, vertices, materials,\n"
    "emitters: faces with emission > 0), total_area, emitting_area, bbox_min,\n"
    "bbox_max, the camera, dropped_degenerate, warnings and one 'warning' line\n"
    "each; the mesh figures (edges, boundary_edges, nonmanifold_edges,\n"
    "misoriented_edges, components, closed, convex_inside, convex = closed and\n"
    "convex seen from inside, pairs_shared_edge[_coplanar],\n"
    "pairs_shared_vertex[_coplanar], surface_mesh); the plan as effect_<name> =\n"
    "on|off and effect_<name>_reason lines.  Then a table of the materials with\n"
    "columns material, name, rho_r, rho_g, rho_b, E_r, E_g, E_b, faces, area.\n"
    "\n"
    "Errors name the problem and its place (file:line for OBJ/MTL, the face\n"
    "index otherwise) and exit with status 2.\n"
    "\n"
    "example: radkit info scenes/cornell/cornell.obj\n";

/* The shortest of %.15g, %.16g, %.17g that reads back as x exactly, so
 * 2.385 prints as 2.385 and every printed number is the stored double. */
static const char *num(char buf[32], double x)
{
    for (int digits = 15; digits <= 17; digits++) {
        snprintf(buf, 32, "%.*g", digits, x);
        if (strtod(buf, NULL) == x)
            break;
    }
    return buf;
}

static const char *onoff(int on) { return on ? "on" : "off"; }

static void print_decision(const char *name, const rad_effect_decision *d)
{
    printf("# effect_%s = %s\n# effect_%s_reason = %s\n", name, onoff(d->on), name, d->reason);
}

int cli_info(int argc, char **argv)
{
    const char *scene_path = NULL;
    int want_help = 0, assimp_check = 0;
    cli_scene_options so;
    cli_scene_options_init(&so);
    cli_option options[5 + CLI_SCENE_OPTION_COUNT] = {
        {"", &scene_path, NULL, "scene"},
        {"--help", NULL, &want_help, NULL},
        {"-h", NULL, &want_help, NULL},
        {"--assimp-check", NULL, &assimp_check, NULL},
    };
    int nopt = 4 + cli_scene_options_add(&so, options + 4);
    options[nopt] = (cli_option){NULL, NULL, NULL, NULL};
    rad_status st = cli_parse("info", argc, argv, 2, options);
    if (st != RAD_OK)
        return cli_fail(st);
    if (want_help) {
        printf("%s%s%s", help_head, cli_scene_options_help, help_tail);
        return 0;
    }
    if (!scene_path)
        return cli_fail(RAD_ERROR(RAD_EINVAL, "info: a SCENE file is required (see 'radkit info --help')"));

    rad_scene_params params;
    rad_effects_params eparams;
    rad_scene_params_default(&params);
    rad_scene_effects_params_default(&eparams);
    if ((st = cli_scene_options_apply("info", &so, &params, &eparams)) != RAD_OK)
        return cli_fail(st);
    /* Assimp's OBJ reader dereferences null on some malformed files; radkit's
     * own reader is the one that decides, so the cross-check is asked for. */
    params.no_cross_check = !assimp_check;

    rad_scene *scene = NULL;
    rad_mesh *mesh = NULL;
    if ((st = rad_scene_load(scene_path, &params, &scene)) != RAD_OK)
        return cli_fail(st);
    st = rad_mesh_create(rad_scene_vertices(scene), rad_scene_vertex_count(scene),
                         rad_scene_triangles(scene), rad_scene_triangle_count(scene),
                         rad_scene_triangle_faces(scene), &mesh);
    rad_effects_plan plan;
    if (st == RAD_OK)
        st = rad_scene_effects_plan(scene, mesh, &eparams, &plan);
    if (st != RAD_OK)
        goto out;

    rad_scene_summary sum;
    rad_scene_summarize(scene, &sum);
    rad_mesh_info info;
    rad_mesh_get_info(mesh, &info);
    const rad_camera *cam = rad_scene_camera(scene);
    printf("# radkit %s info\n", RAD_VERSION);
    char nb[12][32];
    printf("# source = %s\n# scale = %s\n", rad_scene_source(scene), num(nb[0], params.scale));
    printf("# faces = %d\n# vertices = %d\n# materials = %d\n# emitters = %d\n", sum.faces,
           sum.vertices, sum.materials, sum.emitters);
    printf("# total_area = %s\n# emitting_area = %s\n", num(nb[0], sum.total_area),
           num(nb[1], sum.emitting_area));
    printf("# bbox_min = %s %s %s\n# bbox_max = %s %s %s\n", num(nb[0], sum.bbox_min[0]),
           num(nb[1], sum.bbox_min[1]), num(nb[2], sum.bbox_min[2]), num(nb[3], sum.bbox_max[0]),
           num(nb[4], sum.bbox_max[1]), num(nb[5], sum.bbox_max[2]));
    printf("# camera = %s\n# camera_position = %s %s %s\n# camera_look_at = %s %s %s\n",
           cam->from_scene ? "scene" : "default", num(nb[0], cam->position[0]),
           num(nb[1], cam->position[1]), num(nb[2], cam->position[2]), num(nb[3], cam->look_at[0]),
           num(nb[4], cam->look_at[1]), num(nb[5], cam->look_at[2]));
    printf("# camera_up = %s %s %s\n# camera_fov_y_deg = %s\n", num(nb[0], cam->up[0]),
           num(nb[1], cam->up[1]), num(nb[2], cam->up[2]), num(nb[3], cam->fov_y_deg));
    printf("# dropped_degenerate = %d\n# warnings = %d\n", rad_scene_dropped_count(scene),
           rad_scene_warning_count(scene));
    for (int w = 0; w < rad_scene_warning_count(scene); w++)
        printf("# warning = %s\n", rad_scene_warning(scene, w));
    printf("# edges = %d\n# boundary_edges = %d\n# nonmanifold_edges = %d\n"
           "# misoriented_edges = %d\n# components = %d\n# closed_components = %d\n",
           info.edges, info.boundary_edges, info.nonmanifold_edges, info.misoriented_edges,
           info.components, info.closed_components);
    printf("# closed = %s\n# convex_inside = %s\n# convex = %s\n", info.closed ? "yes" : "no",
           info.convex_inside == 1 ? "yes" : info.convex_inside == 0 ? "no" : "unknown",
           info.closed && info.convex_inside == 1 ? "yes" : "no");
    printf("# pairs_shared_edge = %d\n# pairs_shared_edge_coplanar = %d\n"
           "# pairs_shared_vertex = %d\n# pairs_shared_vertex_coplanar = %d\n",
           info.pairs_edge, info.pairs_edge_coplanar, info.pairs_vertex, info.pairs_vertex_coplanar);
    rad_mesh_surface_check sc;
    if (rad_mesh_check_surface(mesh, &sc) == RAD_OK)
        printf("# surface_mesh = %s\n", sc.surface_mesh ? "yes" : "no (not a manifold polygon mesh)");
    else
        printf("# surface_mesh = unknown (%s)\n", rad_error_message());
    printf("# pairs_total = %lld\n# pairs_facing_away = %lld\n# pairs_singular = %d\n",
           plan.pairs_total, plan.pairs_facing_away, plan.pairs_singular);
    const rad_effect_decision *dec[RAD_EFFECT_COUNT];
    const char *names[RAD_EFFECT_COUNT];
    rad_scene_effects_list(&plan, dec, names);
    for (int k = 0; k < RAD_EFFECT_COUNT; k++)
        print_decision(names[k], dec[k]);

    /* The material table: faces and area per material. */
    int nm = rad_scene_material_count(scene), nt = rad_scene_triangle_count(scene);
    const rad_scene_material *mats = rad_scene_materials(scene);
    const int *tmat = rad_scene_triangle_materials(scene), *tri = rad_scene_triangles(scene);
    const double *xyz = rad_scene_vertices(scene);
    printf("material\tname\trho_r\trho_g\trho_b\tE_r\tE_g\tE_b\tfaces\tarea\n");
    for (int m = 0; m < nm; m++) {
        int faces = 0;
        double area = 0.0;
        for (int t = 0; t < nt; t++) {
            if (tmat[t] != m)
                continue;
            const int *v = tri + 3 * t;
            rad_vec3 a = rad_vec3_make(xyz[3 * v[0]], xyz[3 * v[0] + 1], xyz[3 * v[0] + 2]);
            rad_vec3 b = rad_vec3_make(xyz[3 * v[1]], xyz[3 * v[1] + 1], xyz[3 * v[1] + 2]);
            rad_vec3 c = rad_vec3_make(xyz[3 * v[2]], xyz[3 * v[2] + 1], xyz[3 * v[2] + 2]);
            faces++;
            area += rad_geom_triangle_area(a, b, c);
        }
        printf("%d\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%d\t%s\n", m, mats[m].name,
               num(nb[0], mats[m].rho[0]), num(nb[1], mats[m].rho[1]), num(nb[2], mats[m].rho[2]),
               num(nb[3], mats[m].emission[0]), num(nb[4], mats[m].emission[1]),
               num(nb[5], mats[m].emission[2]), faces, num(nb[6], area));
    }
out:
    rad_mesh_destroy(mesh);
    rad_scene_destroy(scene);
    return st == RAD_OK ? 0 : cli_fail(st);
}
