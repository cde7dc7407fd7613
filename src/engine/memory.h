// How the process asks for memory.
#pragma once

namespace odec {

// Large blocks (from 128 kB: the arrays of blocks, contacts and zones) are mapped from the
// system one by one and given back as soon as they are freed, rather than carved from the heap,
// where the hole an array leaves when it grows stays resident; and the free top of the heap is
// given back once it reaches 128 kB. Called once at the start of a program (odec, the
// benchmarks); does nothing where the C library is not glibc.
void tune_allocator();

} // namespace odec
