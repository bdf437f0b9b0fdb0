"""marblevideo benchmarks, each beside its baseline in the same run. From the checkout:

    python -m benchmarks                       # table1 e2e numpy memory (several minutes)
    python -m benchmarks table1 e2e --seconds 4 --device pocl
    python -m benchmarks.live_bench --record rec.mp4   # the parts with options of their own
    python -m benchmarks compare 31a6cd2 --seconds 10  # that commit against this checkout
    python -m benchmarks kernels --profile     # device time per kernel

(``python benchmarks/bench.py PARTS`` before; the parts and options are the same.)

- table1: the paper's Table 1 (frames per second of a blank-sheet design) for a
  12-op recipe in the spirit of its Figure 6 (6 drops, 4 combs, a wave, a
  vortex) at its five sizes and four AA columns; kernel time only (render +
  read back), adaptive and full-pattern sampling, beside the paper's GPU figures.
- e2e: marbling a 1280x720 clip (that recipe, RGSS) with libx264 veryfast crf 23,
  against a plain PyAV decode + encode of the same clip with the same settings
  (plain_transcode.py, as a script of its own and in-process); clips of 4 and 20
  seconds (--seconds), since the CLI's fixed start weighs less on a longer one;
  the animated recipe with the lattice (the default) and with --exact-walk.
- numpy: our renderer against the same recipe computed per frame with NumPy
  float32 inverse maps and cv2.remap (one remap per RGSS subsample).
- memory: peak RSS of the CLI marbling a 1080p clip of 10 s and of 10 minutes (--long).
- pst: a pst-marble-style design (rings, two rakes, a stir, a Lamb-Oseen vortex)
  at 1024x1024 in Table 1's columns, beside the 12-op row.
- svg: SVG export of every bundled blank-sheet sample (time, vertices, size,
  and agreement with the raster render at 2x and 4x, beside the raster's own
  RGSS), and Figure 6 at 1024 and 4096 px by tolerance.
- bullseye: 30 concentric drops and a comb walked with the drops as one run,
  against the same drops with centres 1/1000 px apart (which no run joins).
- bounds: on e2e's clip, what any sampling scheme can reach: the animated
  recipe with one sample per pixel (every pixel walked and gathered once), one
  keyed turn (a walk of next to nothing) with RGSS and with one sample, and the
  plain transcode of the marbled output (x264's cost for marbled pictures).
- series: the bundled samples with rakes and the pst design (rakes and a stir),
  evenly spaced tines and rings summed in closed form (four exponentials an op)
  against one exponential per term, in one program.
- busy: every blank-sheet sample halfway and at its end, the share of pixels
  adaptive sampling lists against its time and the full pattern's.
- animations: every frame of four sample animations at 960x640, the ops that
  have not started skipped by the walk against every op walked.
- cluster: a 720p clip (the e2e recipe, animated) rendered whole, in 4
  segments serially (plan, segments and join timed) and on a local Ray with
  1 and 2 workers (cluster_bench.py; needs the extra 'ray').
- lattice, live1080: the interpolated inverse map of animated frames against
  the exact walk, quality and time, and live at 1080p (lattice_bench.py).
- lanes: the vector width on this CPU: 16 against 8 lanes (and 4), for the code
  PoCL generates for this CPU and for an AVX2 CPU (POCL_KERNELLIB_NAME=avx2),
  each in a process of its own: a blank-sheet frame, a 720p frame over an input
  walked afresh and from reused maps, and a planar 720p frame.
- strokes: the stroke presets at 1024x768 (tulip under 1 s), one stroke of n
  steps against n circle ops, and the packing of a 200000-step stroke
  (stroke_bench.py).
- pst-stir: Jaffer's Wreath and Curl imported from pst-marble, their stirs with
  ``turn`` against the same stirs with ``alpha`` (pst_bench.py).
- kernels: frames of the e2e clip through one renderer by route (I420 static
  with reused maps, animated from the lattice and walked exactly, RGBA), ms
  per frame; with --profile each kernel's device time from a profiling queue
  (kernels_bench.py).
- motion-e2e: the CLI on a 720p clip of three textured discs going round, two
  waves with the recipe's ``motion`` against the same without it (paired rounds),
  and the analysis alone per frame in process (motion_e2e.py).
- compare BASE [HEAD]: the CLI's static and animated e2e commands of two
  commits (HEAD: default this checkout), each checked out into a temporary
  worktree, paired and alternating (A B A B, --rounds), medians of wall time,
  CPU time and peak RSS and of the paired ratios (compare.py).

Benchmarks with options of their own run as modules of the package:
``python -m benchmarks.live_bench`` (live at 720p, --record, --twelve),
``benchmarks.osc_bench`` (OSC to preview latency), ``benchmarks.design_bench``
(the designer's gesture to frame), ``benchmarks.designer_realtime`` (every
gesture's frames per second, latency and agreement with the exact render),
``benchmarks.soak_bench`` (a long live session), ``benchmarks.signals_bench``
(the audio analysis);
``python benchmarks/plain_transcode.py SRC DST`` is a script of its own.

Timings are medians; the machine is shared, so treat differences under 1.3x as noise.
"""
