#!/usr/bin/env bash
# Installs every build and test dependency of dynterrain from Debian packages.
# Idempotent: installs only what is missing. Needs root or sudo.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git iproute2 util-linux
  libeigen3-dev
  liblcm-dev liblcm-bin
  cyclonedds-dev cyclonedds-tools
  libosmesa6-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libcli11-dev libtomlplusplus-dev libspdlog-dev libfmt-dev
  libsqlite3-dev libpng-dev libxxhash-dev libsodium-dev
  libgeographiclib-dev libgdal-dev gdal-bin tshark
  faketime
  clang libclang-rt-14-dev clang-format
  python3 python3-pip
  libcivetweb-dev nlohmann-json3-dev libjs-leaflet chromium
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi

if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  echo "setup: all Debian packages present"
fi

# Playwright drives Debian's chromium in the live view's browser tests (view/test); its own
# browser download is not used (the tests point it at /usr/bin/chromium).
if ! python3 -c 'import playwright' 2>/dev/null; then
  echo "setup: installing the playwright Python module"
  python3 -m pip install --quiet playwright || echo "setup: warning: could not install playwright; the view's browser tests will be skipped"
fi

# LCM's own Python module, used by the cross-language PDU test to decode our traffic.
if ! python3 -c 'import lcm' 2>/dev/null; then
  echo "setup: installing the lcm Python module"
  python3 -m pip install --quiet lcm || echo "setup: warning: could not install the lcm Python module; the Python decode test will be skipped"
fi

# The cyclonedds Python package: its `cyclonedds` CLI reads our typed DDS topics by field name
# (transport_dds_python_subscribe_test). Version 0.10.2 matches Debian's Cyclone DDS; pip builds it
# against the installed C library, looking for CYCLONEDDS_HOME/{include,bin,lib/libddsc.so}.
# Debian keeps the library in the multiarch directory, so a directory of links stands in for the
# install prefix during the build (the package then finds libddsc on the system path).
if ! command -v cyclonedds >/dev/null 2>&1; then
  echo "setup: installing the cyclonedds Python package"
  home="$(mktemp -d)"
  ln -s /usr/include "$home/include"
  ln -s /usr/bin "$home/bin"
  ln -s "/usr/lib/$(gcc -print-multiarch)" "$home/lib"
  CYCLONEDDS_HOME="$home" python3 -m pip install --quiet cyclonedds==0.10.2 ||
    echo "setup: warning: could not install the cyclonedds Python package; the DDS subscribe test will be skipped"
  rm -rf "$home"
fi

# PyPI opendis, an independent DIS implementation: dis_opendis_test has it read our Entity State
# and write one we read (docs/dis.md "Outside peers").
if ! python3 -c 'import opendis' 2>/dev/null; then
  echo "setup: installing the opendis Python module"
  python3 -m pip install --quiet opendis || echo "setup: warning: could not install the opendis Python module; the opendis test will be skipped"
fi
