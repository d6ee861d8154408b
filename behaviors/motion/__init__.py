"""Motion shared by the engines: clips and quaternions, the DeepMimic reader, skeletons and
projection."""
