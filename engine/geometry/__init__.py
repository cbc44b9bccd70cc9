"""Scene geometry that segmenting and editing share: the cameras' frame, support planes, connected pieces on a
voxel grid, the Gaussians' spacing. May import formats and base."""
