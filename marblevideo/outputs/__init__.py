"""Outputs beyond raster frames: resolution-independent SVG of blank-sheet
designs, and designs seen through a UV pass."""
