#!/bin/bash
# specmip render --integrator light on the OpenCL backend under mpirun: two
# ranks give the one process's pixels bit for bit (each pass's splats summed
# in fixed point on the device that renders it, the pass images added in pass
# order), every rank taking passes; rank 1's command line asks for the path
# integrator, which rank 0's overrides. The CPU reference's case is cli_mpi.sh's.
source "$(dirname "$0")/lib_cli.sh"
source "$(dirname "$0")/lib_mpi.sh"
# 48 x 48 at 87 spp: three passes of 29 spp; the ranks meet at their first pass.
two_ranks_same light render "$DATA/scenes/cornell_spiky.scene" --mode ml --width 48 --height 48 --spp 87 \
    --seed 3 --quiet
finish
