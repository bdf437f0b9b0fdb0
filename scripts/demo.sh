#!/usr/bin/env bash
# The main job on the bundled sample: set up, then marble samples/coffee.mp4
# with samples/swirl.json into out/coffee-swirl.mp4 (audio and timing kept).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
mkdir -p out
.venv/bin/marblevideo samples/coffee.mp4 --ops samples/swirl.json -o out/coffee-swirl.mp4 -y
echo "done: out/coffee-swirl.mp4"
