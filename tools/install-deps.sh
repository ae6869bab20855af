#!/bin/sh
# Installs what sphfx needs to build, test and run on Debian 12 (run as root). Idempotent.
# slurm-wlm and munge: the farm tests start a one-node Slurm (tests/farm/); sphfx itself does not need them.
set -eu
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends \
  ca-certificates cmake g++ make pkg-config python3 python3-glad \
  libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri libosmesa6 libosmesa6-dev \
  libopenvdb-dev libboost-dev libboost-iostreams-dev libtbb-dev libblosc-dev \
  libcli11-dev nlohmann-json3-dev libfmt-dev libgtest-dev libpng-dev libopenexr-dev gnuplot-nox \
  slurm-wlm munge \
  >/dev/null
