#!/usr/bin/env bash
# Installs what a fresh machine of this kind lacks (idempotent, quiet when everything is there):
# the Cortex-M target and Rust components, qemu-system-arm from Debian.
set -euo pipefail
cd "$(dirname "$0")/.."

# rust-toolchain.toml names the target and components; any cargo/rustup call installs them.
rustup show active-toolchain >/dev/null

if ! command -v qemu-system-arm >/dev/null; then
  echo "setup: installing qemu-system-arm" >&2
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends qemu-system-arm >/dev/null
fi

# Reference tools for the differential tests and the timing comparison: libFAUDES (`faudes`) and TCT
# (`pitct`) from PyPI, in a venv of their own at .venv.
if ! .venv/bin/python -c "import faudes, pitct" >/dev/null 2>&1; then
  echo "setup: installing libFAUDES and TCT (faudes, pitct) into .venv" >&2
  python3 -m venv .venv
  .venv/bin/pip install --quiet --disable-pip-version-check faudes pitct
fi
