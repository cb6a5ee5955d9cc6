//! ivp (placeholder; being written)
