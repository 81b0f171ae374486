#pragma once
// A bzip2 stream (900 kB blocks) with the bytes libbz2's BZ2_bzBuffToBuffCompress(…, 9, 0, 30) writes for
// the same input (test/record/test_bzip2_encoder.cpp), about 2.5x as fast on a bag's chunks. libbz2 spends
// nine tenths of its time sorting a block's rotations; here libdivsufsort sorts the suffixes of the
// block's least rotation, a Lyndon word, whose suffixes sort as its rotations do. Everything after the
// sort (run lengths, move-to-front, the Huffman tables) follows libbz2's choices step for step, so that the
// output is the same bits. A periodic block has no Lyndon rotation: that input goes to libbz2 whole.
#include <cstddef>
#include <string>

namespace swarm_forage {

/// Replaces `out` with `in` compressed; returns false if libbz2 did it (a periodic block). Throws
/// std::runtime_error if libbz2 fails.
bool bzip2Compress(const char* in, std::size_t n, std::string& out);

}  // namespace swarm_forage
