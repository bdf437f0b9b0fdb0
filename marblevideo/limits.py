"""Every limit and default a user meets, in one place (the README's Limits table).

Each is enforced where the value enters (a recipe, an option, a file header)
with a one-line message, before any work is done.
"""

#: Largest magnitude of any number in a recipe: values stay well inside float32.
NUMBER_LIMIT = 1e30
#: Deepest nesting of lists and objects in a recipe (a valid recipe needs 7).
MAX_DEPTH = 32
#: Largest input image, in pixels (16384 x 16384), judged from the file's header.
MAX_PIXELS = 1 << 28
#: Largest still rendered and encoded in one piece (a JPEG or WebP, or any still to
#: standard output): 16384 x 16384, as an input; PNG and TIFF files are written in
#: bands at any size.
MAX_ONE_PIECE = 1 << 28
#: Largest frame the designer's API renders (``/api/frame.*``, ``/api/layers``), in
#: pixels: an 8K screen's (7680 x 4320) fits; a huge frame took the designer's
#: memory (found by tests/test_api_fuzz.py).
MAX_FRAME_PIXELS = 1 << 25
#: Largest side of a WebP (libwebp's WEBP_MAX_DIMENSION).
WEBP_MAX_SIDE = 16383
#: Largest output (or input) side, in pixels (OpenCL buffers and int indices).
MAX_SIDE = 1 << 15
#: SVG and PDF outlines lie within this many output pixels of the exact design
#: (at the file's own size: 0.2 px at a 4x zoom).
DEFAULT_TOLERANCE = 0.05
#: Frame rate of a blank sheet rendered to video, and of the live test pattern.
DEFAULT_FPS = 30.0
#: Port of the designer's and the live preview's page (on 127.0.0.1).
DEFAULT_PORT = 8765
#: Longest list in a recipe (rake tines, stir radii, layout colours).
MAX_LIST = 256
#: Largest count in a recipe (a layout's drops, a rake's tines up to MAX_LIST).
MAX_COUNT = 4096
#: A URL input whose reads stall this long fails (seconds).
URL_TIMEOUT = 30
#: Highest frame rate (``--fps``), frames per second.
MAX_FPS = 1000.0
#: Latest time and longest length, in seconds (``--time``, ``--start``, ``--end``,
#: ``--duration``, a still animated): a week.
MAX_SECONDS = 7 * 24 * 3600.0
#: Largest pst-marble design file ``marblevideo import`` reads, in bytes.
MAX_DESIGN_BYTES = 1 << 24
#: Most steps one PostScript option of an import may take (each value or name
#: evaluated and each turn of a loop is one), counted before a loop runs.
PS_STEPS = 1_000_000
#: Most values on an import's PostScript stack (an array's items included).
PS_STACK = 100_000
#: Deepest nesting of procedures an import's PostScript may call.
PS_DEPTH = 64
#: Most ops one import may make (its drops, sprays and motions together: a recipe
#: of 8,000 ops took 4.7 s to validate, found by tests/test_fuzz_inputs.py).
MAX_IMPORT_OPS = MAX_COUNT
#: An exported OpenCL program's frame data (every frame's packed values, the frame
#: table and the pattern), in bytes: the constant memory every OpenCL device gives
#: a program (CL_DEVICE_MAX_CONSTANT_BUFFER_SIZE is at least 64 KiB).
EXPORT_CONSTANT_BYTES = 1 << 16
#: The most an export's ``--constant-memory`` may allow (PoCL gives 2 MiB).
EXPORT_MAX_CONSTANT_BYTES = 1 << 24
#: Highest frame rate an export's frames are sampled at (``--fps``).
EXPORT_MAX_FPS = MAX_FPS
#: Most frames an export samples (10 minutes at 30 fps): the recipe settles within them.
EXPORT_MAX_FRAMES = 18000
