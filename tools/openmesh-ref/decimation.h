// OpenMesh's quadric-error decimation (DecimaterT + ModQuadricT) on a fixture, written as
// references.
#pragma once

#include <string>

// Reads INPUT_PLY (the layout openmesh_ref.cc reads) and, when every face is a
// triangle, writes OUTPUT_DIR/decimation/ (see decimation.cc). Throws
// std::runtime_error on failure.
void write_decimation(const std::string& input_ply, const std::string& out_dir);
