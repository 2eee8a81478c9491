"""Claims (d)-(f) read where the paper reads them: alpha_mu, the collapse and the sum rule on deep intruders."""
