#!/usr/bin/env bash
# Installs every Debian 12 package StrataMesh needs to build, test and run its demo.
# Idempotent: packages already present are skipped, and apt is not touched when
# nothing is missing. Needs root (or sudo) and apt-get.
set -euo pipefail

PACKAGES=(
  # compilers and build tools
  build-essential cmake git pkg-config
  # ParaView 5.11 SDK (bundles VTK 9.2) and its Python bindings
  paraview paraview-dev python3-paraview
  # what find_package(ParaView) needs on Debian
  qtbase5-dev qttools5-dev libqt5svg5-dev libqt5x11extras5-dev qtxmlpatterns5-dev-tools
  libqt5opengl5-dev libutfcpp-dev libhdf5-dev libhdf5-mpi-dev libogg-dev libtheora-dev
  libnetcdf-dev libgdal-dev libavcodec-dev libavformat-dev libavutil-dev libswscale-dev
  libgl2ps-dev libglew-dev libtiff-dev libjpeg-dev libpng-dev liblz4-dev liblzma-dev
  libfreetype-dev libdouble-conversion-dev libeigen3-dev libboost-dev mpi-default-dev
  libexpat1-dev libxml2-dev zlib1g-dev libx11-dev libgl-dev python3-dev
  # tests and benchmarks
  libgtest-dev libgmock-dev libbenchmark-dev
  # rendering under a virtual display (demo pictures, GUI test)
  xvfb xauth
  # independent mesh checker (../shared/tools/meshcheck.py)
  python3-shapely python3-scipy
)

log() { printf '[install-deps] %s\n' "$*"; }

if ! command -v dpkg-query >/dev/null 2>&1 || ! command -v apt-get >/dev/null 2>&1; then
  log "error: this script needs Debian's dpkg and apt-get (Debian 12 'bookworm')." >&2
  exit 1
fi

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  log "all ${#PACKAGES[@]} packages already installed"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then
    SUDO="sudo"
  else
    log "error: ${#missing[@]} packages are missing (${missing[*]}) and installing them needs root; run as root or install sudo." >&2
    exit 1
  fi
fi

log "installing ${#missing[@]} missing packages: ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
if ! $SUDO apt-get update -qq; then
  log "error: 'apt-get update' failed; check the network access to Debian's mirrors." >&2
  exit 1
fi
if ! $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"; then
  log "error: 'apt-get install' failed for: ${missing[*]}" >&2
  exit 1
fi
log "done"
