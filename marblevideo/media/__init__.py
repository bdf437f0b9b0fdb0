"""Files and codecs: what an input or output name means, decoding, encoding and the
encoders' options, image files, YUV frames, still outputs written in bands, the items
a video job carries, atomic outputs and progress. Nothing here knows recipes or ops
(the job that runs them is :mod:`marblevideo.jobs`)."""
