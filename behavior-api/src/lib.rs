//! behavior-api (placeholder; being written)
