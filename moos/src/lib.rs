//! moos (placeholder; being written)
