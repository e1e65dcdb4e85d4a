#!/bin/bash
# specmip render --integrator bdpt on the OpenCL backend under mpirun: two
# ranks give the one process's pixels bit for bit (each pass's connected
# paths' splats summed in fixed point on the device that renders it, the pass
# images added in pass order; the record slots' order, which the atomic
# counter makes vary, does not reach the image), every rank taking passes;
# rank 1's command line asks for the path integrator, which rank 0's
# overrides. One device against two: cli_bdpt_cl.sh's split_invariant.
source "$(dirname "$0")/lib_cli.sh"
source "$(dirname "$0")/lib_mpi.sh"
# 48 x 48 at 87 spp: three passes of 29 spp; the ranks meet at their first pass.
two_ranks_same bdpt render "$DATA/scenes/water_caustic.scene" --mode ml --width 48 --height 48 --spp 87 \
    --seed 3 --quiet
finish
