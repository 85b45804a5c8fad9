#define ANSWER 42u
