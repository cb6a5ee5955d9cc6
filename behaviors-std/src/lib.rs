//! behaviors-std (placeholder; being written)
