//! Quality measures: normals, curvature, G1 deviation, isophotes, slices, reports (seed 000 §5.2).
