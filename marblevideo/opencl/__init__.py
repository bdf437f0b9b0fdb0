"""The OpenCL side: choosing a device, building the program from kernels/, and
rendering frames with it (:class:`~marblevideo.opencl.renderer.Renderer`)."""
