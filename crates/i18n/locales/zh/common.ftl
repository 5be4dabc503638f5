common-yes = 是
common-no = 不
common-ok = 好
common-back = 返回
common-minutes = { $minutes } 分钟
