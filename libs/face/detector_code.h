// The namespace of the detector engine's copy that dlib code is compiled into: `portable` unless
// the including file names another (face_detector_engine_avx2.cpp names `avx2`).
#pragma once

#ifndef FACETOOL_DETECTOR_CODE
#define FACETOOL_DETECTOR_CODE portable
#endif
