/* Quadrature rules on the triangle.
 *
 * Every rule here lives on the unit triangle {(s,t): s >= 0, t >= 0, s + t <= 1},
 * the point being a + s (b - a) + t (c - a), with weights summing to 1 (so a
 * rule approximates the MEAN of f; multiply by the area for the integral).
 *
 * 1. Symmetric rules (rad_quad_tri_symmetric).  Witherden & Vincent (2015)
 *    computed fully symmetric rules with positive weights and interior points
 *    for degrees 1-20 \cite{witherden2015}.  The tables are distributed with
 *    PyFR (files pyfr/quadrules/tri/witherden-vincent-n*-d*-sp.txt, PyFR
 *    v1.x, BSD 3-clause licence, Copyright (c) Imperial College London,
 *    https://github.com/PyFR/PyFR) \cite{pyfr}.  Those files list every point
 *    on the triangle (-1,-1), (1,-1), (-1,1) with weights summing to 2; below,
 *    each symmetry orbit is typed in once as one representative point (x, y)
 *    in those same coordinates, with its weight, exactly as in the file (to
 *    the digits a double keeps).  At start-up of a call the orbit is expanded
 *    into its 1, 3 or 6 points by permuting barycentric coordinates and the
 *    coordinates are mapped to the unit triangle (s = (x+1)/2, t = (y+1)/2,
 *    w = w_file / 2).  The test suite checks every table by integrating all
 *    monomials s^a t^b, a + b <= degree, against the exact a! b! / (a+b+2)!,
 *    which catches any mistyped digit.
 * 2. Collapsed (Duffy) Gauss product rules of any order (rad_quad_tri_duffy):
 *    s = u, t = (1 - u) v maps the unit square onto the triangle with Jacobian
 *    (1 - u); with k Gauss-Legendre points in u and v the rule integrates
 *    s^a t^b exactly when a + b + 1 <= 2k - 1, i.e. total degree 2k - 2
 *    \cite{stroud1971}.  Not symmetric, but available for every order. */
#include "rad_quad.h"

#include <math.h>
#include <stddef.h>

/* One symmetry orbit: kind 1 (centroid), 3 (two equal barycentrics) or 6 (all
 * distinct); (x, y) one point of the orbit on the PyFR reference triangle. */
typedef struct orbit {
    int kind;
    double x, y, w;
} orbit;

typedef struct tri_table {
    int degree, npoints, norbits;
    const orbit *orbits;
} tri_table;

/* witherden-vincent-n1-d1-sp.txt */
static const orbit wv_d1[] = {
    {1, -0.33333333333333333333333333333333333333, -0.33333333333333333333333333333333333333, 2.0},
};
/* witherden-vincent-n3-d2-sp.txt */
static const orbit wv_d2[] = {
    {3, -0.66666666666666666666666666666666666667, 0.33333333333333333333333333333333333333,
     0.66666666666666666666666666666666666667},
};
/* witherden-vincent-n6-d4-sp.txt */
static const orbit wv_d4[] = {
    {3, -0.1081030181680702273633414922338960232, -0.7837939636638595452733170155322079536,
     0.44676317935602293139001401686624560874},
    {3, -0.81684757298045851308085707319559698429, 0.63369514596091702616171414639119396858,
     0.21990348731064373527665264980042105793},
};
/* witherden-vincent-n7-d5-sp.txt */
static const orbit wv_d5[] = {
    {1, -0.33333333333333333333333333333333333333, -0.33333333333333333333333333333333333333, 0.45},
    {3, -0.79742698535308732239802527616975234389, 0.59485397070617464479605055233950468778,
     0.25187836108965430519136789100036266732},
    {3, -0.059715871789769820459117580973104798968, -0.88056825642046035908176483805379040206,
     0.26478830557701236147529877566630399935},
};
/* witherden-vincent-n12-d6-sp.txt */
static const orbit wv_d6[] = {
    {3, -0.87382197101699554331933679425836168532, 0.74764394203399108663867358851672337064,
     0.10168981274041363384187361821373796809},
    {3, -0.50142650965817915741672289378596184782, 0.0028530193163583148334457875719236956481,
     0.23357255145275873205057922277115888265},
    {6, -0.89370990031036610529350065673720370601, 0.27300499824279729446028518882409939961,
     0.16570215123674715038710691284088490796},
};
/* witherden-vincent-n15-d7-sp.txt */
static const orbit wv_d7[] = {
    {3, -0.93253870289082430257005654739836752385, 0.8650774057816486051401130947967350477,
     0.033090100221584262071955896945834891238},
    {3, -0.51684523480919288209962646032443600082, 0.033690469618385764199252920648872001638,
     0.25588834246031114556580247036929262133},
    {3, -0.051380614990563531580838528101628435036, -0.89723877001887293683832294379674312993,
     0.15417329237197213566964304166748277293},
    {6, -0.90592671069480953331718004928623004897, 0.50856008110010635471247864925623992738,
     0.11175746580639956167963262884202819059},
};
/* witherden-vincent-n16-d8-sp.txt */
static const orbit wv_d8[] = {
    {1, -0.33333333333333333333333333333333333333, -0.33333333333333333333333333333333333333,
     0.2886312153555743365021822209781292496},
    {3, -0.081414823414553687942368971011661355879, -0.83717035317089262411526205797667728824,
     0.1901832685345692495877922087771686332},
    {3, -0.65886138449647958675541299701707099796, 0.31772276899295917351082599403414199593,
     0.20643474106943650056358310058425806003},
    {3, -0.89890554336593804908315289880680210631, 0.79781108673187609816630579761360421262,
     0.064916995246396160621851856683561193593},
    {6, -0.98321044518008478932557233092141110162, 0.45698478591080856248200075835212392604,
     0.05446062834886998852968938014781784832},
};
/* witherden-vincent-n19-d9-sp.txt */
static const orbit wv_d9[] = {
    {1, -0.33333333333333333333333333333333333333, -0.33333333333333333333333333333333333333,
     0.19427159256559766763848396501457725948},
    {3, -0.12582081701412672546013927112929005464, -0.74835836597174654907972145774141989072,
     0.15565508200954855863347871259880791224},
    {3, -0.62359292876193453951807743906532886378, 0.24718585752386907903615487813065772755,
     0.1592954778544205060657835485280905465},
    {3, -0.020634961602524744432586150327614401262, -0.95873007679495051113482769934477119748,
     0.062669400454278141073709662574418630986},
    {3, -0.91054097321109458026978682006744727, 0.82108194642218916053957364013489454,
     0.051155351317396062523357597117999647955},
    {6, -0.92632317589052743273036480243322979538, 0.48239719756899604138015974704684765487,
     0.086567078754578754578754578754578754579},
};
/* witherden-vincent-n25-d10-sp.txt */
static const orbit wv_d10[] = {
    {1, -0.33333333333333333333333333333333333333, -0.33333333333333333333333333333333333333,
     0.16348665829257193285623736996835522439},
    {3, -0.93588925356611297413803082132702052207, 0.87177850713222594827606164265404104414,
     0.026705937626299132551145956798137306994},
    {3, -0.71567779788687122981567579361808335656, 0.43135559577374245963135158723616671312,
     0.0919159272094894560275758192650956328},
    {6, -0.35637400942232915754980487802790257253, 0.060108237854688056554191347891388233782,
     0.12780981279284809086579746752530664373},
    {6, -0.94076022102254046473232746114791439895, 0.20246665736691849090948578691737561875,
     0.068369296325918857257383168082684580517},
    {6, -0.94326466932012312149912848884373958881, 0.61586120184575813015989980576348821814,
     0.050595515414576768778085581365666435125},
};

#define TABLE(d, n, o) {d, n, (int)(sizeof o / sizeof o[0]), o}
static const tri_table tables[] = {
    TABLE(1, 1, wv_d1),   TABLE(2, 3, wv_d2),   TABLE(4, 6, wv_d4),   TABLE(5, 7, wv_d5),
    TABLE(6, 12, wv_d6),  TABLE(7, 15, wv_d7),  TABLE(8, 16, wv_d8),  TABLE(9, 19, wv_d9),
    TABLE(10, 25, wv_d10),
};
#define NTABLES ((int)(sizeof tables / sizeof tables[0]))

static const tri_table *find_table(int degree)
{
    if (degree < 0)
        return NULL;
    for (int i = 0; i < NTABLES; i++)
        if (tables[i].degree >= degree)
            return &tables[i];
    return NULL;
}

int rad_quad_tri_symmetric_count(int degree, int *exact_degree)
{
    const tri_table *t = find_table(degree);
    if (!t)
        return 0;
    if (exact_degree)
        *exact_degree = t->degree;
    return t->npoints;
}

rad_status rad_quad_tri_symmetric(int degree, double *s, double *t, double *w, int *npoints)
{
    const tri_table *tab = find_table(degree);
    if (!tab)
        return RAD_ERROR(RAD_EINVAL, "no symmetric triangle rule of degree %d (available: 0 to %d)",
                         degree, RAD_QUAD_TRI_MAX_DEGREE);
    int n = 0;
    for (int o = 0; o < tab->norbits; o++) {
        const orbit *ob = &tab->orbits[o];
        /* Barycentric coordinates of the representative: (1 - s - t, s, t). */
        double b1 = 0.5 * (ob->x + 1.0), b2 = 0.5 * (ob->y + 1.0), b0 = 1.0 - b1 - b2;
        double bc[3] = {b0, b1, b2};
        /* The six permutations of (0,1,2); an orbit of 3 uses the first three
         * cyclic ones, which are distinct when two barycentrics are equal. */
        static const int perm[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1},
                                       {0, 2, 1}, {2, 1, 0}, {1, 0, 2}};
        for (int p = 0; p < ob->kind; p++) {
            s[n] = bc[perm[p][1]];
            t[n] = bc[perm[p][2]];
            w[n] = 0.5 * ob->w;
            n++;
        }
    }
    *npoints = n;
    return RAD_OK;
}

rad_status rad_quad_tri_duffy(int k, double *s, double *t, double *w)
{
    if (k < 1 || k > RAD_QUAD_TRI_DUFFY_MAX)
        return RAD_ERROR(RAD_EINVAL, "collapsed Gauss triangle rule needs 1 to %d points per direction, got %d",
                         RAD_QUAD_TRI_DUFFY_MAX, k);
    double x[RAD_QUAD_TRI_DUFFY_MAX], wx[RAD_QUAD_TRI_DUFFY_MAX];
    rad_status st = rad_quad_gauss_legendre(k, x, wx);
    if (st != RAD_OK)
        return st;
    for (int i = 0; i < k; i++)
        for (int j = 0; j < k; j++) {
            int n = i * k + j;
            s[n] = x[i];
            t[n] = (1.0 - x[i]) * x[j];
            /* Jacobian (1 - u); the factor 2 turns the integral over the unit
             * triangle (area 1/2) into its mean. */
            w[n] = 2.0 * wx[i] * wx[j] * (1.0 - x[i]);
        }
    return RAD_OK;
}
