// skelseg tests: memory handed out dirty, so that a kernel which leaves part
// of an unwritten array (kernels/base/UninitialisedStorage.h) unwritten
// fails its test instead of reading zeros by luck.
//
// glibc's M_PERTURB fills every block malloc returns with a fixed byte
// (0xA5 here), large mmapped blocks included; fresh pages would otherwise
// read 0, which is what a forgotten write would leave unnoticed. Elsewhere
// (another C library, or AddressSanitizer's allocator, which ignores
// mallopt) the scope changes nothing and active() says so.
#pragma once

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace skelseg::test {

class DirtyAllocations {
public:
    DirtyAllocations() {
#if defined(__GLIBC__) && defined(M_PERTURB)
        mActive = ::mallopt(M_PERTURB, 0x5A) == 1;
#endif
    }
    ~DirtyAllocations() {
#if defined(__GLIBC__) && defined(M_PERTURB)
        if (mActive) ::mallopt(M_PERTURB, 0);
#endif
    }
    DirtyAllocations(const DirtyAllocations&) = delete;
    DirtyAllocations& operator=(const DirtyAllocations&) = delete;
    /// Whether blocks now come dirty (glibc's allocator).
    bool active() const noexcept {
        return mActive;
    }

private:
    bool mActive = false;
};

}  // namespace skelseg::test
