#pragma once
// The files of a study, HDF5 laid out after H5MD (readable with h5py and h5dump):
//   bed file        a settled bed: complete state with contact histories, the resolved pour
//                   parameters, the surface and depth measured, the packing-fraction profile
//                   (io/bed_file.hpp)
//   run file        a pull: force series, drag and its error, n, theta, Z, P(Z), kappa,
//                   velocity snapshots, the sanity figures, the resolved parameters of the pull
//                   and of its bed (io/run_file.hpp)
//   checkpoint      a bed file plus the pull's record so far (io/checkpoint_file.hpp)
// Every file is written under a temporary name and renamed when complete, and carries
// /granudrag attributes `format` and `version` that readers check (io/file_header.hpp); the
// parameters are stored by key under /parameters/<command> (io/parameter_record.hpp).
#include "io/bed_file.hpp"
#include "io/checkpoint_file.hpp"
#include "io/run_file.hpp"
