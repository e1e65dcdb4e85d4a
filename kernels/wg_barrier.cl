/* The barrier study's kernels (bench/wg_barrier.c): N steps of a dependent
 * chain through the work-item's local-memory slot. A: one step, written to
 * the slot; R(s): slot s read into it. `dense` meets a barrier after every A
 * and every R (two a step), `sparse` the same n steps with half the barriers
 * (its second step reads the item's own slot, which needs none), `plain` none
 * (it reads its own slot only). Work-groups of at most 64. */
#define A a = a * 0.999f + 1.0f; sh[l] = a;
#define R(s) a += sh[s] * 1e-6f;
#define B barrier(CLK_LOCAL_MEM_FENCE);

__kernel void plain(__global float *out, int n)
{
    __local float sh[64];
    uint l = get_local_id(0);
    float a = (float)l;
    for (int i = 0; i < n; i++) {
        A R(l)
    }
    out[get_global_id(0)] = a;
}

__kernel void dense(__global float *out, int n)
{
    __local float sh[64];
    uint l = get_local_id(0), w = get_local_size(0);
    float a = (float)l;
    for (int i = 0; i < n; i++) {
        A B R((l + 1) % w) B
    }
    out[get_global_id(0)] = a;
}

__kernel void sparse(__global float *out, int n)
{
    __local float sh[64];
    uint l = get_local_id(0), w = get_local_size(0);
    float a = (float)l;
    for (int i = 0; i < n / 2; i++) {
        A B R((l + 1) % w) B A R(l)
    }
    out[get_global_id(0)] = a;
}
