"""Live marbling: sources (camera, file, test pattern), the session that renders
them in real time, its preview page, recording and virtual camera."""
