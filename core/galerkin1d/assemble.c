/* Assembly of the Galerkin kernel matrix A and load vector b.
 *
 * One loop over cell pairs (a: test cell in x, c: trial cell in t) asks for the
 * local matrix of the pair, out[alpha][beta] = int int psi_alpha k psi_beta, and
 * adds it at rows a+alpha, columns c+beta (P1), or at (a, c) (P0, where the one
 * local function is 1).  The local matrix comes from the closed forms (exact)
 * or from a tensor Gauss-Legendre rule with K points per direction.
 *
 * The kernel's kink on x = t costs tensor Gauss its order on diagonal cells:
 * the rule integrates |x - t|-like integrands there with an O(1) relative
 * error, i.e. O(h^3) per diagonal entry, which perturbs (M - A)/h by O(h^2)
 * whatever K is.  gauss-split:K integrates each diagonal cell as two triangles
 * (t < x and t > x) with a collapsed Gauss product rule (Duffy 1982), on which
 * the kernel is smooth, and recovers the order of the rule.
 * References: the Galerkin method [atkinson1997]; the collapsed rule [duffy1982]. */
#include "rad_galerkin1d.h"

#include <stdlib.h>
#include <string.h>

#include "rad_quad.h"

typedef struct quad_ctx {
    const rad_galerkin1d_problem *problem;
    int n, K, split;
    double h;
    const double *u, *w; /* Gauss nodes and weights on [0,1] */
} quad_ctx;

static double shape(int nshape, int alpha, double u)
{
    if (nshape == 1)
        return 1.0;
    return alpha == 0 ? 1.0 - u : u;
}

/* Diagonal cell as two triangles.  Triangle t < x: x = p + h u, t = p + h u v,
 * dA = h^2 u du dv; the other triangle swaps the roles of x and t. */
static void local_split(const quad_ctx *q, int nshape, int c, double out[2][2])
{
    double p = c * q->h, h2 = q->h * q->h;
    for (int i = 0; i < q->K; i++)
        for (int j = 0; j < q->K; j++) {
            double outer = q->u[i], inner = q->u[i] * q->u[j];
            double wt = q->w[i] * q->w[j] * h2 * outer;
            double far = p + q->h * outer, near = p + q->h * inner;
            double k_below = q->problem->kernel(far, near); /* x = far, t = near */
            double k_above = q->problem->kernel(near, far); /* x = near, t = far */
            for (int al = 0; al < nshape; al++)
                for (int be = 0; be < nshape; be++)
                    out[al][be] += wt * (shape(nshape, al, outer) * shape(nshape, be, inner) * k_below +
                                         shape(nshape, al, inner) * shape(nshape, be, outer) * k_above);
        }
}

static void local_gauss(const quad_ctx *q, int nshape, int a, int c, double out[2][2])
{
    memset(out, 0, 4 * sizeof(double));
    if (a == c && q->split) {
        local_split(q, nshape, c, out);
        return;
    }
    double h2 = q->h * q->h;
    for (int i = 0; i < q->K; i++) {
        double x = (a + q->u[i]) * q->h;
        for (int j = 0; j < q->K; j++) {
            double t = (c + q->u[j]) * q->h;
            double kw = q->w[i] * q->w[j] * h2 * q->problem->kernel(x, t);
            for (int al = 0; al < nshape; al++)
                for (int be = 0; be < nshape; be++)
                    out[al][be] += kw * shape(nshape, al, q->u[i]) * shape(nshape, be, q->u[j]);
        }
    }
}

static void local_load_gauss(const quad_ctx *q, int c, double out[2])
{
    out[0] = out[1] = 0.0;
    for (int i = 0; i < q->K; i++) {
        double fw = q->w[i] * q->h * q->problem->f((c + q->u[i]) * q->h);
        out[0] += fw * (1.0 - q->u[i]);
        out[1] += fw * q->u[i];
    }
}

rad_status rad_galerkin1d_assemble(const rad_galerkin1d_problem *problem,
                                   rad_galerkin1d_basis basis, rad_galerkin1d_assembly assembly,
                                   int n, double *A, double *b)
{
    if (!problem || !A || !b || n < 1)
        return RAD_ERROR(RAD_EINVAL, "galerkin1d assembly: bad arguments (n = %d)", n);
    int exact = assembly.kind == RAD_GALERKIN1D_EXACT;
    if (exact && (!problem->kernel_is_green || !problem->f_moments))
        return RAD_ERROR(RAD_EINVAL, "problem '%s' has no closed forms for exact assembly",
                         problem->name);
    if (!exact && assembly.points < 1)
        return RAD_ERROR(RAD_EINVAL, "galerkin1d assembly: %d Gauss points", assembly.points);

    size_t dim = rad_galerkin1d_dim(basis, n);
    int nshape = basis == RAD_GALERKIN1D_P1 ? 2 : 1;
    double *nodes = NULL;
    quad_ctx q = {.problem = problem, .n = n, .K = assembly.points, .h = 1.0 / n,
                  .split = assembly.kind == RAD_GALERKIN1D_GAUSS_SPLIT};
    if (!exact) {
        nodes = malloc(2 * (size_t)q.K * sizeof *nodes);
        if (!nodes)
            return RAD_ERROR(RAD_ENOMEM, "galerkin1d assembly: no memory for %d nodes", q.K);
        rad_quad_gauss_legendre(q.K, nodes, nodes + q.K);
        q.u = nodes;
        q.w = nodes + q.K;
    }

    memset(A, 0, dim * dim * sizeof *A);
    memset(b, 0, dim * sizeof *b);
    for (int c = 0; c < n; c++) {
        for (int a = 0; a < n; a++) {
            double local[2][2] = {{0.0, 0.0}, {0.0, 0.0}};
            if (!exact)
                local_gauss(&q, nshape, a, c, local);
            else if (nshape == 1)
                local[0][0] = rad_galerkin1d_green_p0(n, a, c);
            else
                rad_galerkin1d_green_p1_local(n, a, c, local);
            for (int al = 0; al < nshape; al++)
                for (int be = 0; be < nshape; be++)
                    A[(size_t)(a + al) + (size_t)(c + be) * dim] += local[al][be];
        }
        double load[2];
        if (exact)
            problem->f_moments(c * q.h, q.h, load);
        else
            local_load_gauss(&q, c, load);
        if (nshape == 1) {
            b[c] += load[0] + load[1];
        } else {
            b[c] += load[0];
            b[c + 1] += load[1];
        }
    }
    free(nodes);
    return RAD_OK;
}
