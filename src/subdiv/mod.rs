//! Doo–Sabin and Catmull–Clark subdivision, the comparison methods of seed 000 §6.4.
