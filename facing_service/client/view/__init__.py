"""``facing-service view``: a live page of what the service decides, in a browser, without
ROS. A client of the service's keys like ``watch``, never a part of the service."""
