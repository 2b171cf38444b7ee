//! Bad-input audit (being written).
