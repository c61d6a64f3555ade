// A compile error on purpose (a misspelt parameter): the message must name this file and the
// line and column of the misspelt name.
// param alpha 0.01 1 0.3

float brdf(vec3 wi, vec3 wo) {
    float a2 = alpha * alpha;
    return a2 / (a2 * alpah);
}
