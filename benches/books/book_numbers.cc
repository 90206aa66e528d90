// The random numbers of the second book's final scene, drawn as its main.cc draws them (the
// book's rand(), seeded 1 by default): the 400 ground boxes' heights, then the Perlin field the
// marble sphere makes (which takes its own numbers first), then the 1,000 small spheres' centres.
// run.sh writes them into raypool's next-week scene so that both programs trace one world.
// Built against the book's own headers: g++ -O2 -I src/TheNextWeek book_numbers.cc
#include <cstdio>
#include <iostream>

#include "rtweekend.h"
#include "perlin.h"

int main() {
    for (int k = 0; k < 400; k++)
        std::printf("%.17g\n", random_double(1, 101));
    perlin marble;
    for (int k = 0; k < 1000; k++) {
        auto p = point3::random(0, 165);
        std::printf("%.17g %.17g %.17g\n", p.x(), p.y(), p.z());
    }
}
