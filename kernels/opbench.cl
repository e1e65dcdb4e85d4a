/* The operator micro-benchmark (`specmip bench --ops`, host/bench/bench_ops.c):
 * the spectral operations the shade stage is made of, timed alone at each
 * level's layout. As in the earlier study, an operation reads and writes
 * spectra held in memory: each work-item owns R = mask + 1 rows (a power of
 * two) of the scratch buffer and operation i writes row i & mask from row
 * (i + 1) & mask. The mask is a run-time value, so no store can be proven
 * dead and folded away, and the index costs one AND, not a division; the rows
 * of one work-item stay in the cache.
 *   mul    d *= a          (throughput *= reflectance)
 *   fma    d += a * c      (radiance += throughput * emission * scalar)
 *   set    d = a
 *   clear  d = 0
 * Layouts: level l = 5 vectors of float(16>>l); truth = 25 x float16 (1 nm);
 * rgb = one float4. One kernel body for all (OPK), as in shade_body.clh. */
#define OPK(OP, SUF, W, NV, STMT)                                                      \
    __kernel void op_##OP##_##SUF(__global float##W *s, uint mask, uint iters, float c) \
    {                                                                                  \
        __global float##W *base = s + (size_t)get_global_id(0) * (mask + 1u) * NV;     \
        float##W cv = (float##W)(c);                                                   \
        for (uint it = 0; it < iters; it++) {                                          \
            __global float##W *d = base + (it & mask) * NV;                            \
            __global const float##W *a = base + ((it + 1u) & mask) * NV;               \
            for (int k = 0; k < NV; k++)                                               \
                STMT;                                                                  \
        }                                                                              \
        (void)cv;                                                                      \
    }

/* fma per width; float16 as two float8 halves, as in shade_body.clh (a call
 * with float16 arguments draws an ABI warning on CPUs without AVX-512). */
#define FMA16(a, b, c) ((float16)(fma((a).lo, (b).lo, (c).lo), fma((a).hi, (b).hi, (c).hi)))
#define FMA8(a, b, c) fma(a, b, c)
#define FMA4(a, b, c) fma(a, b, c)
#define FMA2(a, b, c) fma(a, b, c)

#define OPS(SUF, W, NV)                                                                \
    OPK(mul, SUF, W, NV, d[k] *= a[k])                                                 \
    OPK(fma, SUF, W, NV, d[k] = FMA##W(a[k], cv, d[k]))                               \
    OPK(set, SUF, W, NV, d[k] = a[k])                                                  \
    OPK(clear, SUF, W, NV, d[k] = (float##W)(0.0f))

OPS(l0, 16, 5)
OPS(l1, 8, 5)
OPS(l2, 4, 5)
OPS(l3, 2, 5)
OPS(truth, 16, 25)
OPS(rgb, 4, 1)
