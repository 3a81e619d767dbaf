/* A test-only stand-in for Windows' bcryptprimitives.dll, for running vbrain.exe under Debian's
 * Wine 8, which lacks it: Rust's standard library imports ProcessPrng from it. This exports
 * ProcessPrng over advapi32's SystemFunction036 (RtlGenRandom). Built by scripts/test-packages.sh
 * with MinGW-w64 and copied next to the executable in a temporary folder only; never shipped. */
#include <windows.h>

BOOLEAN WINAPI SystemFunction036(PVOID buffer, ULONG length);

__declspec(dllexport) BOOL WINAPI ProcessPrng(PBYTE data, SIZE_T length) {
    while (length > 0) {
        ULONG chunk = length > 0x40000000 ? 0x40000000 : (ULONG)length;
        if (!SystemFunction036(data, chunk)) {
            return FALSE;
        }
        data += chunk;
        length -= chunk;
    }
    return TRUE;
}
