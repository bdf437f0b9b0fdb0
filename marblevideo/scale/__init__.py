"""Scale-out: worker pools, on this machine or a Ray cluster
(:mod:`~marblevideo.scale.cluster`), a video rendered as segments in parallel
(:mod:`~marblevideo.scale.segmented`) and many inputs through one recipe
(:mod:`~marblevideo.scale.batch`)."""
