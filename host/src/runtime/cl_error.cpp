#include "brdfbake/error.hpp"

namespace brdfbake {

const char* cl_error_name(int code) {
  switch (code) {
#define BRDFBAKE_CL_ERR(name, value) \
  case value:                        \
    return #name;
    BRDFBAKE_CL_ERR(CL_SUCCESS, 0)
    BRDFBAKE_CL_ERR(CL_DEVICE_NOT_FOUND, -1)
    BRDFBAKE_CL_ERR(CL_DEVICE_NOT_AVAILABLE, -2)
    BRDFBAKE_CL_ERR(CL_COMPILER_NOT_AVAILABLE, -3)
    BRDFBAKE_CL_ERR(CL_MEM_OBJECT_ALLOCATION_FAILURE, -4)
    BRDFBAKE_CL_ERR(CL_OUT_OF_RESOURCES, -5)
    BRDFBAKE_CL_ERR(CL_OUT_OF_HOST_MEMORY, -6)
    BRDFBAKE_CL_ERR(CL_PROFILING_INFO_NOT_AVAILABLE, -7)
    BRDFBAKE_CL_ERR(CL_MEM_COPY_OVERLAP, -8)
    BRDFBAKE_CL_ERR(CL_IMAGE_FORMAT_MISMATCH, -9)
    BRDFBAKE_CL_ERR(CL_IMAGE_FORMAT_NOT_SUPPORTED, -10)
    BRDFBAKE_CL_ERR(CL_BUILD_PROGRAM_FAILURE, -11)
    BRDFBAKE_CL_ERR(CL_MAP_FAILURE, -12)
    BRDFBAKE_CL_ERR(CL_MISALIGNED_SUB_BUFFER_OFFSET, -13)
    BRDFBAKE_CL_ERR(CL_EXEC_STATUS_ERROR_FOR_EVENTS_IN_WAIT_LIST, -14)
    BRDFBAKE_CL_ERR(CL_COMPILE_PROGRAM_FAILURE, -15)
    BRDFBAKE_CL_ERR(CL_LINKER_NOT_AVAILABLE, -16)
    BRDFBAKE_CL_ERR(CL_LINK_PROGRAM_FAILURE, -17)
    BRDFBAKE_CL_ERR(CL_DEVICE_PARTITION_FAILED, -18)
    BRDFBAKE_CL_ERR(CL_KERNEL_ARG_INFO_NOT_AVAILABLE, -19)
    BRDFBAKE_CL_ERR(CL_INVALID_VALUE, -30)
    BRDFBAKE_CL_ERR(CL_INVALID_DEVICE_TYPE, -31)
    BRDFBAKE_CL_ERR(CL_INVALID_PLATFORM, -32)
    BRDFBAKE_CL_ERR(CL_INVALID_DEVICE, -33)
    BRDFBAKE_CL_ERR(CL_INVALID_CONTEXT, -34)
    BRDFBAKE_CL_ERR(CL_INVALID_QUEUE_PROPERTIES, -35)
    BRDFBAKE_CL_ERR(CL_INVALID_COMMAND_QUEUE, -36)
    BRDFBAKE_CL_ERR(CL_INVALID_HOST_PTR, -37)
    BRDFBAKE_CL_ERR(CL_INVALID_MEM_OBJECT, -38)
    BRDFBAKE_CL_ERR(CL_INVALID_IMAGE_FORMAT_DESCRIPTOR, -39)
    BRDFBAKE_CL_ERR(CL_INVALID_IMAGE_SIZE, -40)
    BRDFBAKE_CL_ERR(CL_INVALID_SAMPLER, -41)
    BRDFBAKE_CL_ERR(CL_INVALID_BINARY, -42)
    BRDFBAKE_CL_ERR(CL_INVALID_BUILD_OPTIONS, -43)
    BRDFBAKE_CL_ERR(CL_INVALID_PROGRAM, -44)
    BRDFBAKE_CL_ERR(CL_INVALID_PROGRAM_EXECUTABLE, -45)
    BRDFBAKE_CL_ERR(CL_INVALID_KERNEL_NAME, -46)
    BRDFBAKE_CL_ERR(CL_INVALID_KERNEL_DEFINITION, -47)
    BRDFBAKE_CL_ERR(CL_INVALID_KERNEL, -48)
    BRDFBAKE_CL_ERR(CL_INVALID_ARG_INDEX, -49)
    BRDFBAKE_CL_ERR(CL_INVALID_ARG_VALUE, -50)
    BRDFBAKE_CL_ERR(CL_INVALID_ARG_SIZE, -51)
    BRDFBAKE_CL_ERR(CL_INVALID_KERNEL_ARGS, -52)
    BRDFBAKE_CL_ERR(CL_INVALID_WORK_DIMENSION, -53)
    BRDFBAKE_CL_ERR(CL_INVALID_WORK_GROUP_SIZE, -54)
    BRDFBAKE_CL_ERR(CL_INVALID_WORK_ITEM_SIZE, -55)
    BRDFBAKE_CL_ERR(CL_INVALID_GLOBAL_OFFSET, -56)
    BRDFBAKE_CL_ERR(CL_INVALID_EVENT_WAIT_LIST, -57)
    BRDFBAKE_CL_ERR(CL_INVALID_EVENT, -58)
    BRDFBAKE_CL_ERR(CL_INVALID_OPERATION, -59)
    BRDFBAKE_CL_ERR(CL_INVALID_GL_OBJECT, -60)
    BRDFBAKE_CL_ERR(CL_INVALID_BUFFER_SIZE, -61)
    BRDFBAKE_CL_ERR(CL_INVALID_MIP_LEVEL, -62)
    BRDFBAKE_CL_ERR(CL_INVALID_GLOBAL_WORK_SIZE, -63)
    BRDFBAKE_CL_ERR(CL_INVALID_PROPERTY, -64)
    BRDFBAKE_CL_ERR(CL_INVALID_IMAGE_DESCRIPTOR, -65)
    BRDFBAKE_CL_ERR(CL_INVALID_COMPILER_OPTIONS, -66)
    BRDFBAKE_CL_ERR(CL_INVALID_LINKER_OPTIONS, -67)
    BRDFBAKE_CL_ERR(CL_INVALID_DEVICE_PARTITION_COUNT, -68)
    BRDFBAKE_CL_ERR(CL_PLATFORM_NOT_FOUND_KHR, -1001)
#undef BRDFBAKE_CL_ERR
    default:
      return "unknown OpenCL error";
  }
}

namespace {

// What an error that ends a run (rather than a bug of ours) means for the user.
const char* cl_hint(int code) {
  switch (code) {
    case -4:   // CL_MEM_OBJECT_ALLOCATION_FAILURE
    case -6:   // CL_OUT_OF_HOST_MEMORY
    case -61:  // CL_INVALID_BUFFER_SIZE
      return "the device ran out of memory: try a smaller size, or another device (brdfbake devices)";
    case -5:  // CL_OUT_OF_RESOURCES: also what most drivers report after a watchdog reset
      return "the device ran out of resources, or its driver stopped a launch (a display watchdog): try a "
             "smaller size or another device";
    case -2:     // CL_DEVICE_NOT_AVAILABLE
    case -36:    // CL_INVALID_COMMAND_QUEUE: the queue of a lost device
    case -9999:  // NVIDIA: illegal address / device lost
      return "the device was lost or is not available: check the driver (brdfbake devices) and run again";
    default:
      return nullptr;
  }
}

std::string cl_message(const std::string& call, int code, const std::string& what_for) {
  std::string m = "OpenCL error";
  if (!what_for.empty()) m += " in " + what_for;
  m += ": " + call + " (" + std::to_string(code) + " " + cl_error_name(code) + ")";
  if (const char* hint = cl_hint(code)) m += "; " + std::string(hint);
  return m;
}

}  // namespace

ClError::ClError(const std::string& call, int code, const std::string& what_for)
    : RuntimeFailure(cl_message(call, code, what_for)), call_(call), code_(code) {}

}  // namespace brdfbake
