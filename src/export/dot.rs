//! Graphviz DOT export (placeholder, filled below).
