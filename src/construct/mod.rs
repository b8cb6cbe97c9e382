//! Surface construction from a control mesh (seed 000 §2–4): curve network, ribbons, twists, patches.
