/* The radkit version, printed in every output header. */
#ifndef RAD_VERSION_H
#define RAD_VERSION_H
#define RAD_VERSION "0.1.0"
#endif
