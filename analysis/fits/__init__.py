"""Every fit of a table (regimes, θ, κ, φ, α, Eq. 12's law), its goodness, and fits.json written and read."""
