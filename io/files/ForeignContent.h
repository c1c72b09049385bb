// skelseg: telling what a file holds when it is not the format its name says.
//
// Files reach users through version control and downloads, and what arrives
// is not always the shape: a clone without Git LFS leaves a 130-byte
// pointer ("version https://git-lfs.github.com/spec/v1 ...") under the
// shape's name, a git-annex checkout a pointer path, a failed download an
// HTML error page; and a shape saved under another format's extension (an
// OFF file named .obj) is common. Each reader refused these for a reason that
// sends the user the wrong way: an OBJ reader, which skips statements it does
// not know, said "the mesh has no faces"; the STL reader took any text
// without "solid" for a binary STL and said "binary STL header says
// 845429046 triangles (42271452384 bytes) but the file has 130 bytes"; the
// others "wrong magic". The readers ask refuseForeignContent() only where
// they would otherwise give up, so no file they read changes; the message
// says what the file is and what to do (fetch the content, download it again,
// rename it). Compressed files are told apart first (CompressedContent.h).
#pragma once

#include <string>
#include <string_view>

namespace skelseg {

/// The problem of a file whose bytes are recognisably not a file of the
/// format `expected` ("OFF", "OBJ", "STL", "PLY", "NRRD", "binvox",
/// "OpenVDB"): a Git LFS or git-annex pointer, an HTML page, or a file of
/// another format skelseg reads (by its magic word or first statement; a
/// binary STL by a size that matches its triangle count), e.g. "holds a PLY
/// mesh (its first line is 'ply'), not an OFF file as its name says; rename
/// it to .ply". Empty when nothing is recognised.
std::string foreignContentProblem(std::string_view bytes, std::string_view expected);

/// Throws InputError(name, foreignContentProblem(bytes, expected)) when that
/// is not empty; returns otherwise. Called where a reader would refuse the
/// file anyway.
void refuseForeignContent(const std::string& name, std::string_view bytes,
                          std::string_view expected);

}  // namespace skelseg
