/* The size of `long', as computed by sizeof. */
#define SIZEOF_LONG 8

/* Define to 1 if the system has the type `long long'. */
#define HAVE_LONG_LONG 1

/* The size of `long long', as computed by sizeof. */
#define SIZEOF_LONG_LONG 8
