/* The few CHOLMOD calls of packbench's updatable factor (updatable_factor.rs), behind an
 * opaque handle so that Rust never mirrors cholmod_common's layout. Every function returns 1
 * on success and 0 on failure (CHOLMOD's status or a factor that is not positive definite);
 * none prints. The factor is a simplicial LDL' of a symmetric positive definite matrix A with
 * fill-reducing permutation P (L D L' = P A P'); rows added and deleted are in L's (permuted)
 * indexing, as cholmod_rowadd and cholmod_rowdel take them. */
#include <stdlib.h>
#include <cholmod.h>

typedef struct pb_factor {
    cholmod_common c;
    cholmod_factor *L;
    /* Reused workspace of cholmod_solve2. */
    cholmod_dense *x, *y, *e;
} pb_factor;

void pb_factor_free(pb_factor *f) {
    if (f == NULL) return;
    cholmod_free_factor(&f->L, &f->c);
    cholmod_free_dense(&f->x, &f->c);
    cholmod_free_dense(&f->y, &f->c);
    cholmod_free_dense(&f->e, &f->c);
    cholmod_finish(&f->c);
    free(f);
}

/* The LDL' factor of the n-by-n matrix whose lower triangle is given column-compressed
 * (colptr of n+1, rowind and val of colptr[n] entries). NULL when it is not positive definite
 * or CHOLMOD fails. */
pb_factor *pb_factor_new(int n, const int *colptr, const int *rowind, const double *val) {
    pb_factor *f = calloc(1, sizeof(pb_factor));
    if (f == NULL) return NULL;
    cholmod_start(&f->c);
    f->c.print = 0;
    f->c.error_handler = NULL;
    /* A simplicial LDL' (what rowadd and rowdel modify), computed as one: the supernodal
     * factorisation converted afterwards spent its time in Debian's reference BLAS and in
     * OpenMP's thread wake-ups at N = 1000. */
    f->c.supernodal = CHOLMOD_SIMPLICIAL;
    f->c.final_super = 0;
    f->c.final_ll = 0;
    f->c.final_pack = 0;
    cholmod_sparse a = {0};
    a.nrow = a.ncol = (size_t)n;
    a.nzmax = (size_t)colptr[n];
    a.p = (void *)colptr;
    a.i = (void *)rowind;
    a.x = (void *)val;
    a.stype = -1;
    a.itype = CHOLMOD_INT;
    a.xtype = CHOLMOD_REAL;
    a.dtype = CHOLMOD_DOUBLE;
    a.sorted = 1;
    a.packed = 1;
    f->L = cholmod_analyze(&a, &f->c);
    if (f->L == NULL || !cholmod_factorize(&a, f->L, &f->c) || f->c.status != CHOLMOD_OK ||
        f->L->minor != f->L->n) {
        pb_factor_free(f);
        return NULL;
    }
    if (f->L->is_super || f->L->is_ll) {
        if (!cholmod_change_factor(CHOLMOD_REAL, 0, 0, 0, 0, f->L, &f->c)) {
            pb_factor_free(f);
            return NULL;
        }
    }
    /* A simplicial LDL' exists for some indefinite matrices too: positive definite is D > 0. */
    const int *colptr_l = f->L->p;
    const double *x = f->L->x;
    for (size_t j = 0; j < f->L->n; j++) {
        if (!(x[colptr_l[j]] > 0.0)) {
            pb_factor_free(f);
            return NULL;
        }
    }
    return f;
}

/* The factor given as a simplicial LDL' (n columns of L in L's indexing, colptr of n+1,
 * rowind and val of colptr[n] entries, rows ascending, the diagonal first and holding D_jj)
 * with perm[k] = the row of A at row k of L. NULL when a D_jj is not positive or CHOLMOD fails. */
pb_factor *pb_factor_from_ldl(int n, const int *perm, const int *colptr, const int *rowind,
                              const double *val) {
    pb_factor *f = calloc(1, sizeof(pb_factor));
    if (f == NULL) return NULL;
    cholmod_start(&f->c);
    f->c.print = 0;
    f->c.error_handler = NULL;
    f->L = cholmod_allocate_factor((size_t)n, &f->c);
    if (f->L == NULL) {
        pb_factor_free(f);
        return NULL;
    }
    int *lperm = f->L->Perm, *count = f->L->ColCount;
    for (int k = 0; k < n; k++) {
        lperm[k] = perm[k];
        count[k] = colptr[k + 1] - colptr[k];
    }
    f->L->ordering = CHOLMOD_GIVEN;
    /* Symbolic to numeric simplicial LDL', unpacked (room to grow), columns in order: an
     * identity factor with room for ColCount entries per column. */
    if (!cholmod_change_factor(CHOLMOD_REAL, 0, 0, 0, 1, f->L, &f->c)) {
        pb_factor_free(f);
        return NULL;
    }
    const int *lp = f->L->p;
    int *li = f->L->i, *lnz = f->L->nz;
    double *lx = f->L->x;
    for (int j = 0; j < n; j++) {
        int p = lp[j];
        if (!(val[colptr[j]] > 0.0) || rowind[colptr[j]] != j) {
            pb_factor_free(f);
            return NULL;
        }
        for (int q = colptr[j]; q < colptr[j + 1]; q++, p++) {
            li[p] = rowind[q];
            lx[p] = val[q];
        }
        lnz[j] = colptr[j + 1] - colptr[j];
    }
    f->L->minor = (size_t)n;
    return f;
}

/* perm[k] = the row of A at row k of L. */
void pb_factor_perm(const pb_factor *f, int *perm) {
    const int *p = f->L->Perm;
    for (size_t k = 0; k < f->L->n; k++) perm[k] = p[k];
}

/* The simplicial factor's arrays: column j of L starts at colptr[j] with the diagonal (D_jj)
 * and holds colcount[j] entries, rows ascending; rowind and val hold nzmax entries. Valid
 * until the next change of the factor. */
void pb_factor_columns(const pb_factor *f, const int **colptr, const int **rowind,
                       const double **val, const int **colcount, size_t *nzmax) {
    *colptr = f->L->p;
    *rowind = f->L->i;
    *val = f->L->x;
    *colcount = f->L->nz;
    *nzmax = f->L->nzmax;
}

/* Row and column k of L D L' become (rowind, val) (nnz entries, rows in L's indexing, the
 * diagonal included); row k must be an identity row before. Fails when D_kk ≤ 0. */
int pb_factor_rowadd(pb_factor *f, int k, int nnz, const int *rowind, const double *val) {
    int colptr[2] = {0, nnz};
    cholmod_sparse r = {0};
    r.nrow = f->L->n;
    r.ncol = 1;
    r.nzmax = (size_t)nnz;
    r.p = colptr;
    r.i = (void *)rowind;
    r.x = (void *)val;
    r.stype = 0;
    r.itype = CHOLMOD_INT;
    r.xtype = CHOLMOD_REAL;
    r.dtype = CHOLMOD_DOUBLE;
    r.sorted = 0;
    r.packed = 1;
    if (!cholmod_rowadd((size_t)k, &r, f->L, &f->c) || f->c.status != CHOLMOD_OK) return 0;
    const double dkk = ((const double *)f->L->x)[((const int *)f->L->p)[k]];
    return dkk > 0.0;
}

/* Row and column k of L D L' become those of the identity. */
int pb_factor_rowdel(pb_factor *f, int k) {
    return cholmod_rowdel((size_t)k, NULL, f->L, &f->c) && f->c.status == CHOLMOD_OK;
}

/* b := A⁻¹ b (length n, A's indexing). */
int pb_factor_solve(pb_factor *f, double *b) {
    cholmod_dense rhs = {0};
    rhs.nrow = f->L->n;
    rhs.ncol = 1;
    rhs.nzmax = f->L->n;
    rhs.d = f->L->n;
    rhs.x = b;
    rhs.xtype = CHOLMOD_REAL;
    rhs.dtype = CHOLMOD_DOUBLE;
    if (!cholmod_solve2(CHOLMOD_A, f->L, &rhs, NULL, &f->x, NULL, &f->y, &f->e, &f->c)) return 0;
    const double *x = f->x->x;
    for (size_t k = 0; k < f->L->n; k++) b[k] = x[k];
    return 1;
}
