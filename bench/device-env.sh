# Sourced by the run scripts under bench/results/ that the device tool runs:
# the NVIDIA Vulkan loader's set-up from the carried .gl packages, and the
# carried binaries (.devcarry/pack.tar.xz: bin/ and the libraries they need,
# unpacked to .devcarry/x). Leaves B pointing at the binaries.
for f in .gl/*.deb; do dpkg -x "$f" /; done
ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
export XDG_RUNTIME_DIR=$(mktemp -d)
mkdir -p .devcarry/x && tar xJf .devcarry/pack.tar.xz -C .devcarry/x
export LD_LIBRARY_PATH=$PWD/.devcarry/x/lib
B=.devcarry/x/bin
nvidia-smi --query-gpu=name --format=csv,noheader
