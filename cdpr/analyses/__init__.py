"""Robot in, table out, no files: scans (paths, planes), workspace, DOE, symmetry, error budget,
compensation, uncertainty and calibration."""
