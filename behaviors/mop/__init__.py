"""Action following with template HMMs (MOP, Master of Puppets)."""
