#!/usr/bin/env bash
# Set up marblevideo in ./.venv on Debian/Ubuntu: an OpenCL driver (Debian's PoCL,
# only when no OpenCL driver is registered), then the package and its dependencies.
# Usage: bash scripts/setup.sh [--test]   (--test also installs the test tools and
# the extra 'ray', whose tests start a local Ray cluster)
set -euo pipefail
cd "$(dirname "$0")/.."

as_root() { if [ "$(id -u)" = 0 ]; then "$@"; else sudo "$@"; fi; }
apt_install() {
  if command -v apt-get >/dev/null; then
    as_root apt-get update -qq
    DEBIAN_FRONTEND=noninteractive as_root apt-get install -y -qq "$@" >/dev/null
  else
    echo "setup: please install $* with your package manager" >&2
    exit 1
  fi
}

if ! ls /etc/OpenCL/vendors/*.icd >/dev/null 2>&1; then
  echo "setup: no OpenCL driver registered; installing Debian's PoCL (CPU OpenCL)" >&2
  apt_install pocl-opencl-icd ocl-icd-libopencl1
fi

PY=${PYTHON:-python3}
if [ ! -x .venv/bin/python ]; then
  "$PY" -m venv .venv 2>/dev/null || { apt_install python3-venv; rm -rf .venv; "$PY" -m venv .venv; }
fi
extra=""
[ "${1:-}" = "--test" ] && extra="[test,ray]"
if [ "${1:-}" = "--test" ] && ! command -v chromium >/dev/null; then
  echo "setup: installing Debian's chromium for the live preview's browser tests" >&2
  apt_install chromium
fi
if [ "${1:-}" = "--test" ] && ! command -v ffmpeg >/dev/null; then
  echo "setup: installing Debian's ffmpeg, the independent reader the output tests decode with" >&2
  apt_install ffmpeg
fi
if [ "${1:-}" = "--test" ] && { ! command -v gst-launch-1.0 >/dev/null || ! command -v glslangValidator >/dev/null \
    || ! command -v xvfb-run >/dev/null || ! gst-inspect-1.0 glshader >/dev/null 2>&1 \
    || ! gst-inspect-1.0 avdec_h264 >/dev/null 2>&1; }; then
  echo "setup: installing GStreamer's GL plugins, Xvfb and glslang, the hosts the shader export tests run" >&2
  apt_install gstreamer1.0-gl gstreamer1.0-tools gstreamer1.0-plugins-base gstreamer1.0-plugins-good \
    gstreamer1.0-libav xvfb xauth glslang-tools
fi
if [ "${1:-}" = "--test" ] && [ ! -e /usr/lib/nginx/modules/ngx_rtmp_module.so ]; then
  echo "setup: installing Debian's nginx with its RTMP module, the server the stream tests send to" >&2
  apt_install nginx-light libnginx-mod-rtmp
fi
.venv/bin/python -m pip install -q --disable-pip-version-check --upgrade pip >/dev/null
.venv/bin/python -m pip install -q --disable-pip-version-check -e ".${extra}"
