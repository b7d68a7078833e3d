// The face detector's engine compiled for AVX2 (FaceDetector runs it only on CPUs that have it):
// face_detector_engine.cpp again, its dlib headers and its own code under GCC's target("avx2"),
// and dlib's namespace renamed so that dlib's template code compiled here never stands in for
// the portable copy's at link time. Every standard header is included first, for the baseline
// CPU, so that no standard library code compiled here for AVX2 can replace the program's copy
// (HardPhotos.Avx2CopyDefinesNoSharedAvx2Code checks the object file).
#include <bits/stdc++.h>

#define FACETOOL_DETECTOR_CODE avx2
#define FACETOOL_DETECTOR_AVX2 1
#define FACETOOL_DETECTOR_RENAMED_DLIB 1
#define dlib facetool_dlib_avx2
// dlib chooses its vector code by these (from __AVX__ and the like, which the target pragma
// does not define in C++).
#define DLIB_HAVE_SSE2
#define DLIB_HAVE_SSE3
#define DLIB_HAVE_SSE41
#define DLIB_HAVE_AVX
#define DLIB_HAVE_AVX2
#include "libs/face/face_detector_engine.cpp"
