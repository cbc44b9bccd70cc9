"""Stage 0, a scene in: photos or a video to an undistorted COLMAP folder (`capture`, pycolmap's SfM), the
generator's renders to a scene folder (`build-scene`), and any scene folder loaded as one `Scene`, undistorted
and downscaled into a cache beside it where it needs to be. May import io, formats and base."""
