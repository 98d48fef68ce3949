// Editing references: OpenMesh's TriMesh Euler operators on a fixture (see editing.cc).
#pragma once

#include <string>

// Reads INPUT_PLY (the binary little-endian double layout beltrami-io writes) and writes
// OUTPUT_DIR/editing/{ops.txt,faces.txt,queries.txt}. Throws std::runtime_error on
// failure.
void write_editing_references(const std::string& input_ply, const std::string& out_dir);
