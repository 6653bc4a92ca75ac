// Counts the test binary's heap allocations (a replaced global operator new), so a test can
// check that code reusing its buffers allocates nothing.
#pragma once

namespace test
{
/// operator new calls so far in this process; −1 when not counted (sanitizer builds).
long heapAllocations();
}  // namespace test
