"""The video job: decode -> transform -> encode in three threads
(:mod:`~marblevideo.jobs.pipeline`, :mod:`~marblevideo.jobs.stages`), the transform
stage (:mod:`~marblevideo.jobs.transforms`), frame-rate conversion
(:mod:`~marblevideo.jobs.retime`) and the segments of a split render
(:mod:`~marblevideo.jobs.segments`), over the files and codecs of
:mod:`marblevideo.media`."""
