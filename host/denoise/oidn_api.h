// The part of Intel Open Image Denoise's C API (2.x) that caustica calls,
// declared here: the library comes from PyPI's pyoidn wheel, which ships
// the release's shared libraries but no headers (tools/fetch_oidn.sh).
// Every name, value and signature below is OIDN's public C API as its
// documentation states it (API version 2: oidnGetDeviceInt(dev, "version")
// returns major * 10000 + minor * 100 + patch, which host/denoise/
// denoiser.cpp checks at run time against kOidnApiMajor before any other
// call). Only built where CMake found the library (CAUSTICA_WITH_OIDN).
#pragma once

#include <cstddef>

namespace caustica {
inline constexpr int kOidnApiMajor = 2;  // what these declarations describe
}  // namespace caustica

extern "C" {

typedef struct OIDNDeviceImpl* OIDNDevice;
typedef struct OIDNFilterImpl* OIDNFilter;
typedef struct OIDNBufferImpl* OIDNBuffer;

typedef enum {
  OIDN_DEVICE_TYPE_DEFAULT = 0,
  OIDN_DEVICE_TYPE_CPU = 1,
  OIDN_DEVICE_TYPE_SYCL = 2,
  OIDN_DEVICE_TYPE_CUDA = 3,
  OIDN_DEVICE_TYPE_HIP = 4,
  OIDN_DEVICE_TYPE_METAL = 5,
} OIDNDeviceType;

typedef enum {
  OIDN_ERROR_NONE = 0,
  OIDN_ERROR_UNKNOWN = 1,
  OIDN_ERROR_INVALID_ARGUMENT = 2,
  OIDN_ERROR_INVALID_OPERATION = 3,
  OIDN_ERROR_OUT_OF_MEMORY = 4,
  OIDN_ERROR_UNSUPPORTED_HARDWARE = 5,
  OIDN_ERROR_CANCELLED = 6,
} OIDNError;

typedef enum {
  OIDN_FORMAT_UNDEFINED = 0,
  OIDN_FORMAT_FLOAT = 1,
  OIDN_FORMAT_FLOAT2 = 2,
  OIDN_FORMAT_FLOAT3 = 3,
  OIDN_FORMAT_FLOAT4 = 4,
} OIDNFormat;

typedef enum {
  OIDN_QUALITY_DEFAULT = 0,
  OIDN_QUALITY_FAST = 4,
  OIDN_QUALITY_BALANCED = 5,
  OIDN_QUALITY_HIGH = 6,
} OIDNQuality;

OIDNDevice oidnNewDevice(OIDNDeviceType type);
void oidnReleaseDevice(OIDNDevice device);
void oidnSetDeviceBool(OIDNDevice device, const char* name, bool value);
void oidnSetDeviceInt(OIDNDevice device, const char* name, int value);
int oidnGetDeviceInt(OIDNDevice device, const char* name);
OIDNError oidnGetDeviceError(OIDNDevice device, const char** outMessage);
void oidnCommitDevice(OIDNDevice device);
int oidnGetNumPhysicalDevices(void);
int oidnGetPhysicalDeviceInt(int physicalDeviceID, const char* name);
const char* oidnGetPhysicalDeviceString(int physicalDeviceID, const char* name);

// Buffers the device can reach (a CUDA device cannot read host memory):
// images go in and out through them.
OIDNBuffer oidnNewBuffer(OIDNDevice device, size_t byteSize);
void oidnReleaseBuffer(OIDNBuffer buffer);
void oidnReadBuffer(OIDNBuffer buffer, size_t byteOffset, size_t byteSize, void* dstHostPtr);
void oidnWriteBuffer(OIDNBuffer buffer, size_t byteOffset, size_t byteSize, const void* srcHostPtr);

OIDNFilter oidnNewFilter(OIDNDevice device, const char* type);
void oidnReleaseFilter(OIDNFilter filter);
void oidnSetFilterImage(OIDNFilter filter, const char* name, OIDNBuffer buffer, OIDNFormat format, size_t width,
                        size_t height, size_t byteOffset, size_t pixelByteStride, size_t rowByteStride);
void oidnUnsetFilterImage(OIDNFilter filter, const char* name);
void oidnSetFilterBool(OIDNFilter filter, const char* name, bool value);
void oidnSetFilterInt(OIDNFilter filter, const char* name, int value);
void oidnCommitFilter(OIDNFilter filter);
void oidnExecuteFilter(OIDNFilter filter);

}  // extern "C"
