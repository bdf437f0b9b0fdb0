"""Media in and out: image files, video decode -> transform -> encode (PyAV), the
encoder settings, YUV frames, big stills in bands, atomic outputs and progress."""
