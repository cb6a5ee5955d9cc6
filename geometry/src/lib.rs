//! geometry (placeholder; being written)
