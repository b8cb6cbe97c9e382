//! Exact offsets: Pythagorean-hodograph curves and Pythagorean-normal surfaces (seeds 003/004).
