//! bhv (placeholder; being written)
