/* ProcessPrng for Wine 8 (Debian 12), which lacks bcryptprimitives.dll (Windows has it since
 * 8; Wine since 9.0). Rust's standard library (1.78 and later) draws its random numbers from
 * it. Built with mingw-w64 into the throwaway Wine prefix of scripts/windows.sh only: never
 * shipped (a real Windows has its own). RtlGenRandom is advapi32's SystemFunction036. */
#include <windows.h>

BOOLEAN WINAPI SystemFunction036(PVOID buffer, ULONG length);

BOOL WINAPI ProcessPrng(PBYTE data, SIZE_T length)
{
    while (length > 0) {
        ULONG n = length > 0x7fffffff ? 0x7fffffff : (ULONG)length;
        if (!SystemFunction036(data, n))
            return FALSE;
        data += n;
        length -= n;
    }
    return TRUE;
}
