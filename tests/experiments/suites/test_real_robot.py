"""The real-robot figures' record (Fig. 8, 9, 10): what it says of the networks follows the variant and its params."""

from neurowalk.experiments.suites.real_robot import network_words


def test_the_networks_are_named_with_the_start_weights_of_the_variant_and_its_params():
    assert network_words("paper")["plastic"] == "plastic (paper), weights start at b = 0, q = 0"
    assert network_words("original")["plastic"] == "plastic (original), weights start at b = 2, q = 3"
    assert "weights start at b = 1.5, q = 0" in network_words("paper", {"b_start": 1.5})["plastic"]
    assert network_words("original")["static"] == network_words("paper")["static"] == "static (b = 2.4, c = -3.5)"
