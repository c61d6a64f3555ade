// A compile error on purpose (a misspelt parameter): the message must name this file and the
// line and column of the misspelt name.
// param alpha 0.01 1 0.3

fn brdf(wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    let a2 = alpha * alpha;
    return a2 / (a2 * alpah);
}
