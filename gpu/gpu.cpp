// The gpu/ library's anchor: keeps the library non-empty while its stages land one file at a time.
namespace uvr::gpu {
const char* library_name() { return "uvr_gpu"; }
}  // namespace uvr::gpu
